// The default MRF (pane Psi, unseen cells neutral) on panes at any angle: identical evidence for a
// pane at 0, 25, 45 and 65 deg keeps the same recall, a pane seen in one cell of three keeps its
// cells, and glass cells that disagree with their pane's angle take it.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "glassmap/core/angles.hpp"
#include "glassmap/mrf/refine.hpp"

using namespace glassmap;

namespace {

constexpr int kSize = 64;

// Costs [nats] of a candidate: `best` 0, every other label `others`, EMP `emp`.
void addCandidate(glass::CellEvidence& ev, std::uint32_t cell, int best, float emp, float others) {
  ev.cells.push_back(cell);
  ev.cost.resize(ev.cells.size() * static_cast<std::size_t>(ev.num_labels));
  float* c = &ev.cost[(ev.cells.size() - 1) * static_cast<std::size_t>(ev.num_labels)];
  for (int l = 0; l < ev.num_labels; ++l) c[l] = l == best ? 0.0f : (l == kEmpty ? emp : others);
  ev.label[cell] = static_cast<std::uint8_t>(best);
}

// A 3 m pane through the middle of a 64 x 64 grid at `angle_deg`, rasterised as a thin digital
// line. Every `step`-th pane cell is a glass candidate (glass of its angle bin by `margin` nats
// over EMP); with `flanked`, the cells beside the line are EMP candidates (range noise spreads a
// pane's hits into them: glass there costs 10 nats). With `gap_against` >= 0, the pane cells
// between the glass candidates are EMP candidates too (a floor of direct returns or spurious
// readings put hits in them; glass costs them the prior's 6 nats) whose neutral label costs their
// EMP cost plus `gap_against` nats (their beams' evidence against glass of the pane's angle).
// Every other cell was only crossed by beams.
struct Pane {
  glass::CellEvidence ev;
  std::set<std::uint32_t> glass;  // the pane cells that are candidates
};

Pane pane(double angle_deg, int step, float margin, bool flanked, int spread = 0, float gap_against = -1.0f) {
  Pane p;
  glass::CellEvidence& ev = p.ev;
  ev.geometry.width = kSize;
  ev.geometry.height = kSize;
  ev.geometry.resolution = 0.05;
  ev.label.assign(kSize * kSize, kEmpty);
  const double a = deg2rad(angle_deg);
  const int bin = static_cast<int>(std::lround(std::fmod(angle_deg + 90.0, 180.0) / 5.0)) % 36;  // normal
  std::set<std::uint32_t> line;
  for (int k = -30; k <= 30; ++k) {
    const int x = static_cast<int>(std::floor(32.0 + k * std::cos(a))),
              y = static_cast<int>(std::floor(32.0 + k * std::sin(a)));
    line.insert(static_cast<std::uint32_t>(y * kSize + x));
  }
  std::set<std::uint32_t> flank;
  if (flanked)
    for (const std::uint32_t c : line)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto n = static_cast<std::uint32_t>(static_cast<int>(c) + dy * kSize + dx);
          if (!line.count(n)) flank.insert(n);
        }
  int k = 0;
  std::set<std::uint32_t> all;
  for (const std::uint32_t c : line)
    if (k++ % step == 0) p.glass.insert(c);
  all.insert(p.glass.begin(), p.glass.end());
  all.insert(flank.begin(), flank.end());
  if (gap_against >= 0.0f) all.insert(line.begin(), line.end());
  for (const std::uint32_t c : all) {  // candidates in ascending cell order
    ev.neutral_cost.push_back(std::numeric_limits<float>::infinity());
    if (line.count(c) && !p.glass.count(c)) {
      addCandidate(ev, c, kEmpty, 0.0f, 6.0f);
      ev.neutral_cost.back() = gap_against;
    } else if (p.glass.count(c)) {
      // With `spread`, the normal estimates wander over bin - spread .. bin + spread along the pane
      // (a wide lobe does that), in a fixed pattern.
      const int wander = spread == 0 ? 0 : static_cast<int>(c * 7u % static_cast<unsigned>(2 * spread + 1)) - spread;
      addCandidate(ev, c, glassLabel((bin + wander + 36) % 36), margin, 10.0f);
    } else {
      addCandidate(ev, c, kEmpty, 0.0f, 10.0f);
      for (int l = 0; l < ev.num_labels; ++l)
        ev.cost[(ev.cells.size() - 1) * ev.num_labels + l] = l == kEmpty ? 0.0f : 10.0f;
    }
  }
  return p;
}

double recallAfterMrf(const Pane& p, const mrf::RefineOptions& o = {}) {
  glass::CellEvidence ev = p.ev;
  mrf::refine(ev, o);
  std::size_t kept = 0;
  for (const std::uint32_t c : p.glass) kept += isGlass(ev.label[c]) ? 1 : 0;
  return static_cast<double>(kept) / static_cast<double>(p.glass.size());
}

}  // namespace

TEST(PanePsi, SameRecallAtEveryAngle) {
  for (const float margin : {1.5f, 3.0f}) {
    const double at0 = recallAfterMrf(pane(0.0, 1, margin, true));
    for (const double angle : {25.0, 45.0, 65.0}) {
      const double r = recallAfterMrf(pane(angle, 1, margin, true));
      EXPECT_NEAR(r, at0, 0.02) << "margin " << margin << " angle " << angle;
      EXPECT_GE(r, 0.95) << "margin " << margin << " angle " << angle;
    }
  }
  // The closed table charges the cells beside the pane too: the same evidence loses the pane.
  mrf::RefineOptions closed;
  closed.psi = mrf::PsiKind::Closed;
  EXPECT_LT(recallAfterMrf(pane(25.0, 1, 1.5f, true), closed), 0.5);
}

TEST(PanePsi, APaneSeenInOneCellOfThreeKeepsItsCells) {
  for (const double angle : {0.0, 25.0, 45.0, 65.0, 110.0}) {
    EXPECT_EQ(recallAfterMrf(pane(angle, 3, 1.0f, false)), 1.0) << angle;
    // The paper's grid charges every empty neighbour: it drops them.
    glass::CellEvidence ev = pane(angle, 3, 1.0f, false).ev;
    mrf::RefineOptions paper;
    paper.psi = mrf::PsiKind::Paper;
    paper.unseen_glass_neutral = false;
    mrf::refine(ev, paper);
    EXPECT_EQ(ev.countGlass(), 0u) << angle;
  }
}

TEST(PanePsi, NormalEstimatesInAdjacentBinsAreOnePane) {
  for (const double angle : {0.0, 25.0, 65.0}) {
    // Glass over EMP by 1.5 nats, weighed 3 against Psi at the default MRF weight of 2.
    EXPECT_GE(recallAfterMrf(pane(angle, 1, 1.5f, true, 1)), 0.95) << angle;
    // Charging any two glass labels the full 3 breaks the pane into pieces and empties them.
    mrf::RefineOptions flat;
    flat.pane_angle_full_deg = 1e-6;
    EXPECT_LT(recallAfterMrf(pane(angle, 1, 1.5f, true, 1), flat), 0.8) << angle;
  }
}

TEST(PanePsi, GapsWithHitsThatCannotTellGlassFromEmptyCostThePaneNothing) {
  for (const double angle : {0.0, 25.0, 45.0, 65.0, 110.0}) {
    // The gaps' beams never met the pane near its normal: as free next to glass as cells no beam
    // ended in.
    EXPECT_EQ(recallAfterMrf(pane(angle, 3, 0.5f, false, 0, 0.0f)), 1.0) << angle;
    mrf::RefineOptions off;
    off.candidates_neutral = false;
    EXPECT_LT(recallAfterMrf(pane(angle, 3, 0.5f, false, 0, 0.0f), off), 0.5) << angle;
    // Gaps whose beams met the pane's normal and passed hold evidence against it: they charge.
    EXPECT_LT(recallAfterMrf(pane(angle, 3, 0.5f, false, 0, 5.0f)), 0.5) << angle;
  }
}
