#pragma once
/// The passes over a log run over its scans in parallel (oneTBB), each thread filling its own
/// partial result, merged afterwards. Every partial result here is a sum of integers (saturating
/// counts, fixed-point sums), so the merged result is the same bytes on any number of threads.

#include <atomic>
#include <cstddef>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "glassmap/grid/scan_integration.hpp"

namespace glassmap::grid {

/// Calls body(scan, scan_index, local) for every scan of the log, in parallel (a spooled log block
/// by block, each block's scans in parallel); `local` is the calling thread's element of `locals`.
/// progress(fraction) is called from the calling thread only.
template <class Local, class Body>
void forScansInParallel(const LaserLog& log, const Progress& progress, tbb::enumerable_thread_specific<Local>& locals,
                        Body&& body) {
  const std::thread::id caller = std::this_thread::get_id();
  const std::size_t n = log.scanCount();
  std::atomic<std::size_t> done{0};
  forEachScanBlock(log, [&](std::span<const LaserScan> block, std::size_t first) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, block.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        Local& local = locals.local();
                        for (std::size_t s = r.begin(); s != r.end(); ++s) body(block[s], first + s, local);
                        const std::size_t d = done.fetch_add(r.size()) + r.size();
                        if (progress && std::this_thread::get_id() == caller)
                          progress(static_cast<double>(d) / static_cast<double>(n));
                      });
  });
  if (progress) progress(1.0);
}

/// Sums the statistics of the thread-local parts.
inline IntegrationStats& operator+=(IntegrationStats& a, const IntegrationStats& b) {
  a.scans += b.scans;
  a.beams += b.beams;
  a.hit_beams += b.hit_beams;
  a.cells_traversed += b.cells_traversed;
  return a;
}

}  // namespace glassmap::grid
