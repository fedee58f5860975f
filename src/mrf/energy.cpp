#include "glassmap/mrf/energy.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap::mrf {
namespace {

int32_t scaled(double cost) { return static_cast<int32_t>(std::lround(cost * kCostScale)); }

// Forward half of the 8-neighbourhood: each unordered neighbour pair is visited once.
constexpr int kForward[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};

}  // namespace

std::vector<int32_t> makePsi(int num_glass_bins, const PsiWeights& w) {
  if (num_glass_bins < 1) throw Error("need at least one glass bin", {}, 0, "num_glass_bins");
  const int n = kFirstGlass + num_glass_bins;
  std::vector<int32_t> psi(static_cast<std::size_t>(n) * n, 0);
  auto set = [&](int a, int b, double v) {
    psi[a * n + b] = scaled(v);
    psi[b * n + a] = scaled(v);
  };
  set(kEmpty, kOccupied, w.empty_occ);
  for (int a = kFirstGlass; a < n; ++a) {
    set(a, kEmpty, w.glass_empty);
    set(a, kOccupied, w.glass_occ);
    for (int b = kFirstGlass; b < n; ++b) {
      if (a != b) set(a, b, w.glass_glass);
    }
  }
  return psi;
}

std::vector<int32_t> paperPsi(int num_glass_bins, double w_diff, double w_glass_empty) {
  PsiWeights w;
  w.glass_glass = w_diff;
  w.glass_empty = w_glass_empty;
  return makePsi(num_glass_bins, w);
}

const char* toString(PsiKind kind) {
  switch (kind) {
    case PsiKind::Paper: return "paper";
    case PsiKind::Closed: return "closed";
    case PsiKind::Neutral: return "neutral";
    case PsiKind::Pane: return "pane";
  }
  return "?";
}

PsiKind parsePsi(const std::string& name) {
  for (PsiKind k : {PsiKind::Paper, PsiKind::Closed, PsiKind::Neutral, PsiKind::Pane})
    if (name == toString(k)) return k;
  throw Error("unknown Psi '" + name + "' (expected paper, closed, neutral or pane)", {}, 0, "psi");
}

double edgeClassAngle(int cls) {
  constexpr double kAngles[4] = {0.0, 0.75 * kPi, 0.5 * kPi, 0.25 * kPi};
  return kAngles[cls & 3];
}

std::vector<int32_t> psiDirectionTables(PsiKind kind, int num_glass_bins, const PsiWeights& w) {
  if (kind != PsiKind::Pane) return {};
  if (num_glass_bins < 1) throw Error("need at least one glass bin", {}, 0, "num_glass_bins");
  const int n = kFirstGlass + num_glass_bins;
  const std::size_t nn = static_cast<std::size_t>(n) * n;
  std::vector<int32_t> tables(4 * nn, 0);
  for (int cls = 0; cls < 4; ++cls) {
    int32_t* t = tables.data() + cls * nn;
    auto set = [&](int a, int b, double v) {
      t[a * n + b] = scaled(v);
      t[b * n + a] = scaled(v);
    };
    for (int a = kFirstGlass; a < n; ++a) {
      const double normal = (a - kFirstGlass) * kPi / num_glass_bins;
      const double c = std::cos(edgeClassAngle(cls) - (normal + 0.5 * kPi));
      const double f = w.pane_isotropic + (1.0 - w.pane_isotropic) * c * c;
      set(a, kEmpty, w.glass_empty * f);
      set(a, kOccupied, w.glass_empty * f);
      for (int b = kFirstGlass; b < n; ++b) {
        if (a == b) continue;
        const double d = std::abs(a - b) * kPi / num_glass_bins;
        const double apart = std::min(d, kPi - d);  // normals are directions mod 180 deg
        set(a, b, w.glass_glass * std::min(1.0, apart / deg2rad(std::max(w.pane_angle_full_deg, 1e-9))));
      }
    }
  }
  return tables;
}

std::vector<int32_t> psiTable(PsiKind kind, int num_glass_bins, const PsiWeights& pane_weights) {
  PsiWeights w;
  switch (kind) {
    case PsiKind::Paper: return paperPsi(num_glass_bins);
    case PsiKind::Closed: w.glass_occ = w.glass_empty; break;
    case PsiKind::Neutral: w.empty_occ = w.glass_empty; break;
    case PsiKind::Pane: {
      const std::vector<int32_t> dir = psiDirectionTables(kind, num_glass_bins, pane_weights);
      const std::size_t nn = dir.size() / 4;
      std::vector<int32_t> bound(dir.begin(), dir.begin() + static_cast<std::ptrdiff_t>(nn));
      for (std::size_t cls = 1; cls < 4; ++cls)
        for (std::size_t i = 0; i < nn; ++i) bound[i] = std::max(bound[i], dir[cls * nn + i]);
      return bound;
    }
  }
  return makePsi(num_glass_bins, w);
}

void setPsi(LabelEnergy& e, PsiKind kind, int num_glass_bins, const PsiWeights& pane_weights) {
  e.pairwise = psiTable(kind, num_glass_bins, pane_weights);
  e.pairwise_dir = psiDirectionTables(kind, num_glass_bins, pane_weights);
}

void validate(const LabelEnergy& e) {
  if (e.width <= 0 || e.height <= 0) throw Error("grid size must be positive", {}, 0, "width/height");
  if (e.num_labels < 1 || e.num_labels > 65535) throw Error("label count out of range", {}, 0, "num_labels");
  if (e.unary.size() != e.cells() * e.num_labels) throw Error("expected cells x labels unary costs", {}, 0, "unary");
  if (e.pairwise.size() != static_cast<std::size_t>(e.num_labels) * e.num_labels)
    throw Error("expected labels x labels pairwise costs", {}, 0, "pairwise");
  for (int a = 0; a < e.num_labels; ++a)
    for (int b = 0; b < a; ++b)
      if (e.psi(a, b) != e.psi(b, a)) throw Error("pairwise table is not symmetric", {}, 0, "pairwise");
  if (!e.pairwise_dir.empty()) {
    const std::size_t nn = static_cast<std::size_t>(e.num_labels) * e.num_labels;
    if (e.pairwise_dir.size() != 4 * nn)
      throw Error("expected 4 x labels x labels direction tables", {}, 0, "pairwise_dir");
    for (int cls = 0; cls < 4; ++cls)
      for (int a = 0; a < e.num_labels; ++a)
        for (int b = 0; b < a; ++b) {
          if (e.psi(a, b, cls) != e.psi(b, a, cls))
            throw Error("direction table is not symmetric", {}, 0, "pairwise_dir");
          if (e.psi(a, b, cls) > e.psi(a, b))
            throw Error("pairwise must bound every direction table", {}, 0, "pairwise");
        }
  }
  if (!e.active.empty() && e.active.size() != e.cells())
    throw Error("active mask must have one entry per cell", {}, 0, "active");
  if (!e.candidates.empty()) {
    if (e.candidates.size() != e.cells())
      throw Error("candidate sets must have one entry per cell", {}, 0, "candidates");
    if (e.num_labels > 64) throw Error("candidate sets need at most 64 labels", {}, 0, "candidates");
  }
}

int64_t energy(const LabelEnergy& e, const std::vector<uint16_t>& labels) {
  if (labels.size() != e.cells()) throw Error("one label per cell expected", {}, 0, "labels");
  int64_t total = 0;
  for (int y = 0; y < e.height; ++y) {
    for (int x = 0; x < e.width; ++x) {
      const std::size_t c = static_cast<std::size_t>(y) * e.width + x;
      const int lc = labels[c];
      total += e.u(c, lc);
      for (int cls = 0; cls < 4; ++cls) {  // kForward[cls] has direction class cls
        const int nx = x + kForward[cls][0], ny = y + kForward[cls][1];
        if (nx < 0 || nx >= e.width || ny >= e.height) continue;
        total += e.psi(lc, labels[static_cast<std::size_t>(ny) * e.width + nx], cls);
      }
    }
  }
  return total;
}

std::vector<uint16_t> argminLabels(const LabelEnergy& e) {
  std::vector<uint16_t> labels(e.cells());
  for (std::size_t c = 0; c < e.cells(); ++c) {
    const int32_t* row = &e.unary[c * e.num_labels];
    labels[c] = static_cast<uint16_t>(std::min_element(row, row + e.num_labels) - row);
  }
  return labels;
}

namespace {

std::size_t restrict(LabelEnergy& e, int64_t margin, const std::vector<int64_t>* gaps) {
  const int n = e.num_labels;
  e.candidates.assign(e.cells(), 0);
  std::size_t kept = 0;
  const uint64_t all = n == 64 ? ~uint64_t{0} : (uint64_t{1} << n) - 1;
  for (std::size_t c = 0; c < e.cells(); ++c) {
    const int32_t* row = &e.unary[c * n];
    const auto [lo, hi] = std::minmax_element(row, row + n);
    uint64_t set = 0;
    if (*lo == *hi) {
      set = all;  // no excess anywhere: every label is kept (gaps and margins are >= 0)
    } else {
      const int best = static_cast<int>(lo - row);
      const int64_t* gap = gaps ? &(*gaps)[static_cast<std::size_t>(best) * n] : nullptr;
      for (int l = 0; l < n; ++l) {
        const int64_t excess = int64_t{row[l]} - row[best];
        // Lossless: l is dominated by best when its unary excess exceeds anything the neighbours
        // can give back by switching from best to l; then best strictly improves any labelling.
        const bool keep = gap ? excess <= gap[l] : excess <= margin;
        if (keep || l == best) set |= uint64_t{1} << l;
      }
    }
    e.candidates[c] = set;
    kept += static_cast<std::size_t>(std::popcount(set));
  }
  return kept;
}

}  // namespace

std::vector<int64_t> candidateGaps(const LabelEnergy& e) {
  validate(e);
  const int n = e.num_labels;
  std::vector<int64_t> gap(static_cast<std::size_t>(n) * n, 0);
  for (int l = 0; l < n; ++l)
    for (int m = 0; m < n; ++m) {
      int64_t g = std::numeric_limits<int64_t>::min();
      for (int k = 0; k < n; ++k)
        for (int cls = 0; cls < (e.pairwise_dir.empty() ? 1 : 4); ++cls)
          g = std::max<int64_t>(g, int64_t{e.psi(m, k, cls)} - e.psi(l, k, cls));
      gap[static_cast<std::size_t>(m) * n + l] = 8 * std::max<int64_t>(g, 0);  // cells have at most 8 neighbours
    }
  return gap;
}

std::size_t restrictCandidates(LabelEnergy& e, int64_t margin) {
  validate(e);
  if (e.num_labels > 64) throw Error("candidate sets need at most 64 labels", {}, 0, "candidates");
  if (margin >= 0) return restrict(e, margin, nullptr);
  const std::vector<int64_t> gaps = candidateGaps(e);
  return restrict(e, margin, &gaps);
}

std::size_t restrictCandidates(LabelEnergy& e, const std::vector<int64_t>& gaps) {
  validate(e);
  if (e.num_labels > 64) throw Error("candidate sets need at most 64 labels", {}, 0, "candidates");
  if (gaps.size() != static_cast<std::size_t>(e.num_labels) * e.num_labels)
    throw Error("a gap table of another label count", {}, 0, "gaps");
  return restrict(e, -1, &gaps);
}

void writeInstance(const std::string& path, const LabelEnergy& e) {
  if (!e.pairwise_dir.empty())
    throw Error("the instance format holds one pairwise table: direction-dependent Psi (pane) cannot be written", path,
                0, "pairwise_dir");
  validate(e);
  std::string bytes;
  bytes.reserve(12 + 4 * (e.unary.size() + e.pairwise.size()));
  auto put = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<char>((v >> (8 * i)) & 0xFFU));
  };
  put(static_cast<uint32_t>(e.width));
  put(static_cast<uint32_t>(e.height));
  put(static_cast<uint32_t>(e.num_labels));
  for (int32_t v : e.unary) put(static_cast<uint32_t>(v));
  for (int32_t v : e.pairwise) put(static_cast<uint32_t>(v));
  writeAtomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out.flush()) throw Error("cannot write instance file", tmp.string());
  });
}

LabelEnergy readInstance(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open instance file", path);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t pos = 0;
  auto get = [&](const char* field) {
    if (pos + 4 > bytes.size()) throw Error("file ends early", path, 0, field);
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t{static_cast<unsigned char>(bytes[pos + i])} << (8 * i);
    pos += 4;
    return v;
  };
  LabelEnergy e;
  const uint32_t w = get("width"), h = get("height"), l = get("labels");
  if (w == 0 || h == 0 || w > (1U << 16) || h > (1U << 16) || l == 0 || l > 65535)
    throw Error("implausible header", path, 0, "width/height/labels");
  e.width = static_cast<int>(w);
  e.height = static_cast<int>(h);
  e.num_labels = static_cast<int>(l);
  const std::size_t expected = 12 + 4 * (e.cells() * l + std::size_t{l} * l);
  if (bytes.size() != expected)
    throw Error("size " + std::to_string(bytes.size()) + " bytes, header implies " + std::to_string(expected), path, 0,
                "unary/pairwise");
  e.unary.resize(e.cells() * l);
  for (auto& v : e.unary) v = static_cast<int32_t>(get("unary"));
  e.pairwise.resize(std::size_t{l} * l);
  for (auto& v : e.pairwise) v = static_cast<int32_t>(get("pairwise"));
  validate(e);
  return e;
}

}  // namespace glassmap::mrf
