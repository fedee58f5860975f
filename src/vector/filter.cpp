// Step 4 of vectorize(): pieces the evidence does not support are dropped (too few cells, too
// short, a blob, glass whose angle labels disagree with its line or that is cut out of a blob).
#include "piece.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "glassmap/core/angles.hpp"

namespace glassmap::vector::detail {

// Share of a glass piece's cells whose angle label agrees with the fitted pane normal.
namespace {

double labelAgreement(const Piece& p, const CellCloud& cloud, double max_angle_deg) {
  const double cos_max = std::cos(deg2rad(max_angle_deg));
  const Vec2 n = p.normal();
  std::size_t agree = 0;
  for (const std::uint32_t i : p.ids)
    if (std::abs(cloud.normals[i].dot(n)) >= cos_max) ++agree;
  return p.ids.empty() ? 0.0 : static_cast<double>(agree) / static_cast<double>(p.ids.size());
}

// Share of a glass piece's cells that have glass cells `across` [m] away across the line: about 0
// for a pane (one to three cells thick), high for a strip cut out of a blob.
double sideCrowding(const Piece& p, const CellCloud& cloud, double across) {
  const Vec2 off = across * p.normal();
  const auto glassAt = [&](const Vec2& q) {
    const int x = static_cast<int>(std::floor(q.x() / cloud.resolution - cloud.origin_cells.x()));
    const int y = static_cast<int>(std::floor(q.y() / cloud.resolution - cloud.origin_cells.y()));
    return x >= 0 && y >= 0 && x < cloud.width && y < cloud.height &&
           cloud.index[static_cast<std::size_t>(y) * cloud.width + x] >= 0;
  };
  std::size_t crowded = 0;
  for (const std::uint32_t i : p.ids)
    if (glassAt(cloud.points[i] + off) || glassAt(cloud.points[i] - off)) ++crowded;
  return p.ids.empty() ? 1.0 : static_cast<double>(crowded) / static_cast<double>(p.ids.size());
}

// Where to look for more glass across a pane: past the band its cells may occupy (voting takes a
// pane's cells within max_distance and claims those within twice that), side_crowding_cells on.
double sideCrowdingDistance(const MaterialOptions& mo, const Context& ctx) {
  const double res = ctx.grid.resolution;
  const double band = ctx.opt.glass_voting ? 2.0 * mo.max_distance : res;
  return band + ctx.opt.side_crowding_cells * res;
}

}  // namespace

// Drops pieces the evidence does not support: too few cells, too short, a blob, or (glass) cells
// whose angle labels disagree with the line through them.
void filterPieces(std::vector<Piece>& pieces, Material material, const MaterialOptions& mo, const CellCloud& cloud,
                  const Context& ctx) {
  for (Piece& p : pieces) {
    if (!p.alive) continue;
    const double width = std::max(cloud.resolution, p.faces_merged ? cloud.resolution : p.thickness);
    // Glass wider than the band its cells are taken from (a pane seen at a slant by a noisy laser)
    // must be the longer for it, by the square of the excess: a blob of one label, and two blobs
    // in a row, are short for their width.
    const double excess = material == Material::Glass ? std::max(1.0, width / (2.0 * mo.max_distance)) : 1.0;
    if (p.ids.size() < mo.min_cells || p.length() < mo.min_length ||
        p.length() < mo.min_elongation * width * excess * excess ||
        (material == Material::Glass &&
         (labelAgreement(p, cloud, mo.max_angle_deg) < mo.min_label_agreement ||
          sideCrowding(p, cloud, sideCrowdingDistance(mo, ctx)) > ctx.opt.max_side_crowding))) {
      p.alive = false;
      ++ctx.stats.dropped;
    }
  }
  compact(pieces);
}
}  // namespace glassmap::vector::detail
