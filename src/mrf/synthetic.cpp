#include "glassmap/mrf/synthetic.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>
#include <random>

#include "glassmap/core/error.hpp"

namespace glassmap::mrf {
namespace {

struct Rect {
  int x0, y0, x1, y1;  // half-open
};

class FloorBuilder {
 public:
  FloorBuilder(const SyntheticOptions& o, std::vector<uint16_t>& truth) : o_(o), truth_(truth), rng_(o.seed) {}

  void build() {
    const int w = o_.width, h = o_.height;
    // Outer walls, two cells thick.
    fill({0, 0, w, 2}, kOccupied);
    fill({0, h - 2, w, h}, kOccupied);
    fill({0, 0, 2, h}, kOccupied);
    fill({w - 2, 0, w, h}, kOccupied);
    split({2, 2, w - 2, h - 2});
    for (const Rect& r : rooms_) furnish(r);
  }

 private:
  int uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  bool chance(double p) { return std::uniform_real_distribution<double>(0, 1)(rng_) < p; }

  void set(int x, int y, uint16_t l) {
    if (x >= 0 && y >= 0 && x < o_.width && y < o_.height) truth_[static_cast<std::size_t>(y) * o_.width + x] = l;
  }
  void fill(const Rect& r, uint16_t l) {
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) set(x, y, l);
  }

  // Recursive split into rooms; each split is a two-cell wall run with a door and maybe glass.
  void split(const Rect& r) {
    const int rw = r.x1 - r.x0, rh = r.y1 - r.y0;
    const bool vertical = rw >= rh;  // wall along y, splitting x
    const int len = vertical ? rw : rh;
    if ((rw <= o_.max_room && rh <= o_.max_room) || len < 2 * o_.min_room + 2) {
      rooms_.push_back(r);
      return;
    }
    const int pos = (vertical ? r.x0 : r.y0) + uniform(o_.min_room, len - o_.min_room - 2);
    const int run0 = vertical ? r.y0 : r.x0, run1 = vertical ? r.y1 : r.x1;
    const int run = run1 - run0;
    for (int s = run0; s < run1; ++s) {
      for (int t = 0; t < 2; ++t) vertical ? set(pos + t, s, kOccupied) : set(s, pos + t, kOccupied);
    }
    if (chance(o_.glass_fraction)) {
      // One-cell-thick pane over part of the run; the pane normal is across the run.
      const int k = vertical ? 0 : 18;
      const int glen = run * uniform(40, 80) / 100, g0 = run0 + uniform(0, run - glen);
      for (int s = g0; s < g0 + glen; ++s) {
        vertical ? set(pos, s, glassLabel(k)) : set(s, pos, glassLabel(k));
        vertical ? set(pos + 1, s, kEmpty) : set(s, pos + 1, kEmpty);
      }
    }
    const int door = run0 + uniform(2, std::max(2, run - 12));
    for (int s = door; s < std::min(run1, door + 8); ++s)
      for (int t = 0; t < 2; ++t) vertical ? set(pos + t, s, kEmpty) : set(s, pos + t, kEmpty);
    if (vertical) {
      split({r.x0, r.y0, pos, r.y1});
      split({pos + 2, r.y0, r.x1, r.y1});
    } else {
      split({r.x0, r.y0, r.x1, pos});
      split({r.x0, pos + 2, r.x1, r.y1});
    }
  }

  void furnish(const Rect& r) {
    const int rw = r.x1 - r.x0, rh = r.y1 - r.y0;
    if (rw < 16 || rh < 16) return;
    const int boxes = uniform(0, 3);
    for (int i = 0; i < boxes; ++i) {
      const int bw = uniform(2, 6), bh = uniform(2, 6);
      const int bx = uniform(r.x0 + 5, r.x1 - 5 - bw), by = uniform(r.y0 + 5, r.y1 - 5 - bh);
      fill({bx, by, bx + bw, by + bh}, kOccupied);
    }
    if (chance(o_.diagonal_fraction)) {
      int kdir = uniform(2, 34);  // pane direction k*5 deg, not axis-aligned
      if (kdir == 18) kdir = 19;
      const double phi = kdir * 5.0 * std::numbers::pi / 180.0;
      const double len = std::min(rw, rh) * uniform(30, 60) / 100.0;
      const double cx = (r.x0 + r.x1) / 2.0, cy = (r.y0 + r.y1) / 2.0;
      const uint16_t label = static_cast<uint16_t>(glassLabel((kdir + 18) % kDefaultBins));
      for (double t = -len / 2; t <= len / 2; t += 0.25)
        set(static_cast<int>(std::floor(cx + t * std::cos(phi))), static_cast<int>(std::floor(cy + t * std::sin(phi))),
            label);
    }
  }

  const SyntheticOptions& o_;
  std::vector<uint16_t>& truth_;
  std::mt19937_64 rng_;
  std::vector<Rect> rooms_;
};

}  // namespace

SyntheticInstance makeSyntheticInstance(const SyntheticOptions& o, const std::vector<int32_t>& psi) {
  if (o.width < 8 || o.height < 8) throw Error("synthetic floor too small", {}, 0, "width/height");
  if (psi.size() != static_cast<std::size_t>(numLabels()) * numLabels())
    throw Error("Psi must be 38 x 38", {}, 0, "psi");
  SyntheticInstance inst;
  LabelEnergy& e = inst.energy;
  e.width = o.width;
  e.height = o.height;
  e.num_labels = numLabels();
  e.pairwise = psi;
  inst.truth.assign(e.cells(), kEmpty);
  FloorBuilder(o, inst.truth).build();

  // Chessboard distance to the nearest structure cell, up to o.band + 1.
  const int w = o.width, h = o.height;
  std::vector<uint8_t> dist(e.cells(), 255);
  std::deque<uint32_t> queue;
  for (std::size_t c = 0; c < e.cells(); ++c)
    if (inst.truth[c] != kEmpty) {
      dist[c] = 0;
      queue.push_back(static_cast<uint32_t>(c));
    }
  while (!queue.empty()) {
    const uint32_t c = queue.front();
    queue.pop_front();
    if (dist[c] > o.band) continue;
    const int x = static_cast<int>(c % w), y = static_cast<int>(c / w);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        const std::size_t n = static_cast<std::size_t>(ny) * w + nx;
        if (dist[n] != 255) continue;
        dist[n] = static_cast<uint8_t>(dist[c] + 1);
        queue.push_back(static_cast<uint32_t>(n));
      }
  }

  // Unary = noisy negative log posterior [nats] of a classifier that confuses glass with
  // neighbouring angles, with OCC and with EMP (glass is mostly invisible), then scaled.
  std::mt19937_64 rng(o.seed ^ 0x9E3779B97F4A7C15ULL);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  e.unary.resize(e.cells() * numLabels());
  double c[numLabels()];
  for (std::size_t cell = 0; cell < e.cells(); ++cell) {
    const int t = inst.truth[cell];
    const bool near = dist[cell] <= o.band;
    if (t == kEmpty) {
      std::fill(c, c + numLabels(), near ? 4.5 : 8.0);
      c[kEmpty] = 0.0;
      c[kOccupied] = near ? 3.0 : 8.0;
    } else if (t == kOccupied) {
      std::fill(c, c + numLabels(), 3.5);
      c[kEmpty] = 3.0;
      c[kOccupied] = 0.0;
    } else {
      const int k = t - kFirstGlass;
      for (int j = 0; j < kDefaultBins; ++j) {
        const int dk = std::min((j - k + kDefaultBins) % kDefaultBins, (k - j + kDefaultBins) % kDefaultBins);
        c[glassLabel(j)] = dk == 0 ? 0.0 : dk == 1 ? 1.2 : dk == 2 ? 2.5 : 4.5;
      }
      c[kEmpty] = 2.5;
      c[kOccupied] = 2.5;
    }
    const double sigma = near ? o.noise : 0.3;
    for (double& v : c) v += sigma * gauss(rng);
    if (near && unit(rng) < o.salt) c[std::uniform_int_distribution<int>(0, numLabels() - 1)(rng)] -= 3.5;
    const double lo = *std::min_element(c, c + numLabels());
    for (int l = 0; l < numLabels(); ++l)
      e.unary[cell * numLabels() + l] = static_cast<int32_t>(std::lround((c[l] - lo) * o.unary_scale * kCostScale));
  }
  return inst;
}

double GlassScore::f1() const {
  return truth_glass + found_glass == 0 ? 1.0 : 2.0 * true_positive / double(truth_glass + found_glass);
}

GlassScore scoreGlass(const std::vector<uint16_t>& truth, const std::vector<uint16_t>& labels) {
  if (truth.size() != labels.size()) throw Error("truth and labels differ in size", {}, 0, "labels");
  GlassScore s;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const bool tg = isGlass(truth[i]), lg = isGlass(labels[i]);
    s.truth_glass += tg;
    s.found_glass += lg;
    s.true_positive += tg && lg;
    s.angle_correct += tg && truth[i] == labels[i];
    s.glass_to_occ += tg && labels[i] == kOccupied;
    s.glass_to_emp += tg && labels[i] == kEmpty;
    s.wrong_cells += truth[i] != labels[i];
  }
  return s;
}

}  // namespace glassmap::mrf
