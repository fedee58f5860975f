// The max-range code of a log (see laser_scan.hpp).
#include "glassmap/core/laser_scan.hpp"

#include <algorithm>
#include <cmath>

#include "glassmap/core/scan_spool.hpp"

namespace glassmap {
namespace {
constexpr double kSlack = 0.005;          // readings within this of the code share it [m]
constexpr std::size_t kMinBeams = 8;      // ... at this many beam indices at least
constexpr std::size_t kBeamSlots = 8192;  // beam indices told apart (more wrap around)
}  // namespace

void MaxRangeCodeFinder::mark(Laser& l, std::size_t beam) {
  if (l.distinct_beams >= kMinBeams) return;
  if (l.beams.empty()) l.beams.assign(kBeamSlots, false);
  const std::size_t slot = beam % kBeamSlots;
  if (!l.beams[slot]) {
    l.beams[slot] = true;
    ++l.distinct_beams;
  }
}

void MaxRangeCodeFinder::add(int laser_id, float range, std::size_t beam) {
  if (!std::isfinite(range) || range <= 0.0f) return;
  Laser& l = lasers_[laser_id];
  const double r = range;
  ++l.readings;
  if (r > l.top + kSlack) {  // a new top: the readings near the old one no longer count
    l.below = std::max(l.below, l.top);
    l.top = r;
    l.at_top = 1;
    l.beams.assign(l.beams.size(), false);
    l.distinct_beams = 0;
    mark(l, beam);
  } else if (r >= l.top - kSlack) {
    ++l.at_top;
    l.top = std::max(l.top, r);
    mark(l, beam);
  } else {
    l.below = std::max(l.below, r);
  }
}

double MaxRangeCodeFinder::longestBelowCode(int laser_id) const {
  const auto it = lasers_.find(laser_id);
  return it == lasers_.end() ? 0.0 : it->second.below;
}

double MaxRangeCodeFinder::code(int laser_id, std::size_t* readings) const {
  const auto it = lasers_.find(laser_id);
  if (it == lasers_.end()) return 0.0;
  const Laser& l = it->second;
  // A far corner a standing robot sees again and again is one or two beams; a code is everywhere.
  const bool spike = l.top >= 1.0 && l.at_top >= 5 && l.distinct_beams >= kMinBeams &&
                     static_cast<double>(l.at_top) >= 0.001 * static_cast<double>(l.readings);
  if (!spike) return 0.0;
  if (readings) *readings = l.at_top;
  return l.top;
}

void MaxRangeCodeFinder::record(LogReadStats& stats) const {
  for (const auto& [id, l] : lasers_) {
    std::size_t n = 0;
    const double c = code(id, &n);
    if (c > stats.max_range_code) {
      stats.max_range_code = c;
      stats.max_range_code_readings = n;
    }
  }
}

std::map<int, double> MaxRangeCodeFinder::codes() const {
  std::map<int, double> out;
  for (const auto& entry : lasers_)
    if (const double c = code(entry.first); c > 0.0) out[entry.first] = c;
  return out;
}

void applyMaxRangeCode(LaserScan& s, double code) {
  // A code at or above the header's maximum is a max reading already: nothing to change.
  if (s.max_range <= 0.0 || code < s.max_range) s.max_range = code - kSlack;
}

bool markMaxRangeCode(LaserLog& log) {
  MaxRangeCodeFinder finder;
  forEachScanBlock(log, [&](std::span<const LaserScan> block, std::size_t) {
    for (const LaserScan& s : block)
      for (std::size_t i = 0; i < s.ranges.size(); ++i) finder.add(s.laser_id, s.ranges[i], i);
  });
  return applyMaxRangeCodes(log, finder);
}

bool applyMaxRangeCodes(LaserLog& log, const MaxRangeCodeFinder& finder) {
  const std::map<int, double> codes = finder.codes();
  for (LaserScan& s : log.scans)
    if (const auto it = codes.find(s.laser_id); it != codes.end()) applyMaxRangeCode(s, it->second);
  if (log.spooled) log.spooled->max_range_codes = codes;
  finder.record(log.stats);
  return !codes.empty();
}

namespace {

class BorrowedScans final : public ScanStore {
 public:
  explicit BorrowedScans(const std::vector<LaserScan>& scans) : scans_(scans) {}
  std::size_t size() const override { return scans_.size(); }
  void forEachBlock(std::size_t block_bytes,
                    const std::function<void(std::vector<LaserScan>& block, std::size_t first)>& f) const override {
    std::vector<LaserScan> block;
    std::size_t first = 0, bytes = 0;
    for (std::size_t i = 0; i < scans_.size(); ++i) {
      block.push_back(scans_[i]);
      bytes += scans_[i].memoryBytes();
      if (bytes >= block_bytes || i + 1 == scans_.size()) {
        f(block, first);
        first = i + 1;
        block.clear();
        bytes = 0;
      }
    }
  }

 private:
  const std::vector<LaserScan>& scans_;
};

}  // namespace

std::shared_ptr<const ScanStore> borrowScans(const std::vector<LaserScan>& scans) {
  return std::make_shared<BorrowedScans>(scans);
}

std::size_t LaserLog::scanCount() const { return spooled ? spooled->spool->size() : scans.size(); }

void forEachScanBlock(const LaserLog& log,
                      const std::function<void(std::span<const LaserScan> block, std::size_t first)>& f) {
  if (!log.spooled) {
    if (!log.scans.empty()) f(std::span<const LaserScan>(log.scans), 0);
    return;
  }
  const SpooledScans& sp = *log.spooled;
  sp.spool->forEachBlock(sp.block_bytes, [&](std::vector<LaserScan>& block, std::size_t first) {
    for (LaserScan& s : block) {
      if (!sp.shift.isZero()) s.laser_pose.t -= sp.shift;
      if (const auto it = sp.max_range_codes.find(s.laser_id); it != sp.max_range_codes.end())
        applyMaxRangeCode(s, it->second);
    }
    f(std::span<const LaserScan>(block), first);
  });
}

}  // namespace glassmap
