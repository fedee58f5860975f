#include "line_votes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace glassmap::glass::sparse {
namespace {

// Line votes: (1-degree angle bin, offset bin) per weak return, the angle axis padded by `pad` bins
// on both sides with the wrapped votes (angle + pi is the same line with the offset negated), so
// that a window around any angle sums every vote within it.
class Votes {
 public:
  Votes(double rho_max, double rho_step, int pad)
      : step_(rho_step),
        pad_(pad),
        half_(static_cast<int>(std::ceil(rho_max / rho_step))),
        rows_(kAngleBins + 2 * pad),
        cols_(2 * half_ + 1),
        sum_(static_cast<std::size_t>(rows_ + 1) * (cols_ + 1), 0) {
    count_.assign(static_cast<std::size_t>(rows_) * cols_, 0);
  }
  void add(double angle, double rho) {
    const int b = sparse::angleBinOf(angle);
    put(b + pad_, rho);
    if (b < pad_) put(b + kAngleBins + pad_, -rho);
    if (b >= kAngleBins - pad_) put(b - kAngleBins + pad_, -rho);
  }
  // Summed-area table of the counts.
  void integrate() {
    for (int r = 0; r < rows_; ++r)
      for (int c = 0; c < cols_; ++c)
        sum_[idx(r + 1, c + 1)] = count_[static_cast<std::size_t>(r) * cols_ + c] + sum_[idx(r, c + 1)] +
                                  sum_[idx(r + 1, c)] - sum_[idx(r, c)];
  }
  // Votes within +-wa angle bins and +-wr offset bins of (row, col).
  std::int64_t window(int row, int col, int wa, int wr) const {
    const int r0 = std::max(0, row - wa), r1 = std::min(rows_, row + wa + 1);
    const int c0 = std::max(0, col - wr), c1 = std::min(cols_, col + wr + 1);
    return sum_[idx(r1, c1)] - sum_[idx(r0, c1)] - sum_[idx(r1, c0)] + sum_[idx(r0, c0)];
  }
  int rows() const { return rows_; }
  int cols() const { return cols_; }
  Line line(int row, int col) const { return {(row - pad_ + 0.5) * kPi / kAngleBins, (col - half_) * step_}; }

 private:
  void put(int row, double rho) {
    const int c = static_cast<int>(std::lround(rho / step_)) + half_;
    if (c >= 0 && c < cols_) ++count_[static_cast<std::size_t>(row) * cols_ + c];
  }
  std::size_t idx(int r, int c) const { return static_cast<std::size_t>(r) * (cols_ + 1) + c; }
  double step_;
  int pad_, half_, rows_, cols_;
  std::vector<std::int64_t> sum_;
  std::vector<std::int32_t> count_;
};

}  // namespace

// Seed lines: local maxima of the votes summed over +-pad angle bins and +-wr offset bins, with at
// least min_votes, strongest first. Offsets are voted relative to the grid's centre.
std::vector<Line> seedLines(const std::vector<WeakReturn>& weak, const grid::GridGeometry& g, int pad, int wr,
                            int min_votes) {
  const Vec2 centre = 0.5 * (g.origin + g.maxCorner());
  Votes votes(0.5 * (g.maxCorner() - g.origin).norm() + 1.0, g.resolution, pad);
  for (const WeakReturn& r : weak) votes.add(r.normal, Vec2(std::cos(r.normal), std::sin(r.normal)).dot(r.at - centre));
  votes.integrate();
  struct Peak {
    std::int64_t votes;
    int row, col;
  };
  std::vector<Peak> peaks;
  for (int row = pad; row < pad + kAngleBins; ++row)
    for (int col = 0; col < votes.cols(); ++col) {
      const std::int64_t v = votes.window(row, col, pad, wr);
      if (v < min_votes) continue;
      bool maximum = true;
      for (int dr = -1; dr <= 1 && maximum; ++dr)
        for (int dc = -1; dc <= 1 && maximum; ++dc)
          if ((dr || dc) && row + dr >= 0 && row + dr < votes.rows() && col + dc >= 0 && col + dc < votes.cols())
            maximum = votes.window(row + dr, col + dc, pad, wr) <= v;
      if (maximum) peaks.push_back({v, row, col});
    }
  std::stable_sort(peaks.begin(), peaks.end(), [](const Peak& a, const Peak& b) { return a.votes > b.votes; });
  std::vector<Line> lines;
  for (const Peak& peak : peaks) {
    Line line = votes.line(peak.row, peak.col);
    line.rho += line.normal().dot(centre);
    lines.push_back(line);
  }
  return lines;
}

}  // namespace glassmap::glass::sparse
