// map_log: the mapping pipeline as `glassmap map` runs it, and its result.
#include <chrono>

#include "common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/core/labels.hpp"
#include "glassmap/io/sensor_profile.hpp"
#include "glassmap/pipeline/map_files.hpp"

namespace glassmap::python {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::shared_ptr<Log> logFrom(const py::object& obj, const LogReadOptions& read, const std::string& what,
                             double max_memory_mb) {
  if (py::isinstance<Log>(obj)) return obj.cast<std::shared_ptr<Log>>();
  const std::filesystem::path p = toPath(obj, what);
  auto log = std::make_shared<Log>();
  log->path = p.string();
  py::gil_scoped_release release;
  try {
    log->log = readLog(p, read, &log->notes);
  } catch (const Error& e) {
    if (max_memory_mb <= 0.0 || e.message().find("(the memory limit)") == std::string::npos) throw;
    throw Error(e.message() + ": raise max_memory (now " + std::to_string(static_cast<long long>(max_memory_mb)) +
                    " MB) or map a part of the log",
                e.file(), e.line(), e.field());
  }
  return log;
}

void bindMap(py::module_& m) {
  py::class_<MapRun, std::shared_ptr<MapRun>>(m, "MapResult", "What map_log made of a log.")
      .def_property_readonly(
          "labels",
          [](const MapRun& r) {
            const glass::CellEvidence& e = r.result.evidence;
            const int w = e.geometry.width, h = e.geometry.height;
            py::array_t<std::uint8_t> out({static_cast<py::ssize_t>(h), static_cast<py::ssize_t>(w)});
            auto a = out.mutable_unchecked<2>();
            for (int row = 0; row < h; ++row)  // row 0 = north (top), as in labels.tif
              for (int col = 0; col < w; ++col)
                a(row, col) = labelToCode(e.label[static_cast<std::size_t>(h - 1 - row) * w + col]);
            return out;
          },
          "label codes (height x width uint8, row 0 = north/top as in labels.tif): 0 unknown, 1 empty,\n"
          "2 occupied, 10 + k glass with pane normal at k * 5 deg")
      .def_property_readonly(
          "geotransform",
          [](const MapRun& r) {
            const auto& g = r.result.evidence.geometry;
            const double top = g.origin.y() + g.height * g.resolution;
            return py::make_tuple(g.origin.x(), g.resolution, 0.0, top, 0.0, -g.resolution);
          },
          "GDAL geotransform of labels (x0, cell, 0, y_top, 0, -cell) [m]")
      .def_property_readonly(
          "resolution", [](const MapRun& r) { return r.result.evidence.geometry.resolution; }, "cell size [m]")
      .def_property_readonly(
          "segments", [](const MapRun& r) { return r.result.floorplan.map.segments; },
          "the fitted floorplan's segments (list of Segment)")
      .def_property_readonly(
          "floorplan",
          [](const MapRun& r) {
            Floorplan f;
            f.map = r.result.floorplan.map;
            return f;
          },
          "the fitted floorplan as a Floorplan")
      .def_property_readonly(
          "stats", [](const MapRun& r) { return toPython(pipeline::mapStatsJson(r.result, r.options, r.info)); },
          "the run's figures: the content of `glassmap map`'s stats.json ('files' once written)")
      .def_property_readonly(
          "profile", [](const MapRun& r) { return toPython(pipeline::profileJson(r.result.profile)); },
          "the sensor profile the final pass used (a dict as read_sensor_profile gives)")
      .def(
          "write",
          [](MapRun& r, const py::object& dir) {
            const std::filesystem::path d = toPath(dir, "write(dir)");
            const auto t0 = std::chrono::steady_clock::now();
            std::vector<std::filesystem::path> files;
            {
              py::gil_scoped_release release;
              files = pipeline::writeMapFiles(d, r.result, r.floorplan_files);
            }
            pipeline::MapRunInfo info = r.info;
            info.seconds_total += secondsSince(t0);
            info.peak_memory_bytes = pipeline::peakMemoryBytes();
            info.files.clear();
            for (const auto& f : files) info.files.push_back(f.filename().string());
            // Written last: a folder with a stats.json holds the complete set it lists.
            const nlohmann::json j = pipeline::mapStatsJson(r.result, r.options, info);
            pipeline::writeJsonFile(d / pipeline::kMapManifest, j);
            r.info = info;
            py::list out;
            for (const auto& f : files) out.append(py::str(f.string()));
            out.append(py::str((d / pipeline::kMapManifest).string()));
            return out;
          },
          py::arg("dir"),
          "Writes what `glassmap map -o dir` writes (map.yaml/.pgm, labels.tif, map.png, sensor.yaml, the\n"
          "floorplan files unless no_vector, stats.json last); returns the paths written.")
      .def("__repr__", [](const MapRun& r) {
        const auto& g = r.result.evidence.geometry;
        return "<glassmap.MapResult " + std::to_string(g.width) + "x" + std::to_string(g.height) +
               " glass_cells=" + std::to_string(r.result.stats.glass_cells) +
               " segments=" + std::to_string(r.result.floorplan.map.segments.size()) + ">";
      });

  m.def(
      "map_log",
      [](const py::object& log_or_path, const py::kwargs& kwargs) {
        const auto t0 = std::chrono::steady_clock::now();
        Options o("map_log", kwargs);
        auto run = std::make_shared<MapRun>();
        pipeline::MapOptions& options = run->options;
        auto& mp = options.mapping;
        std::string method = "mrf", solver = "expansion", psi = "pane";
        o.get("method", method);
        o.get("mrf_solver", solver);
        o.get("mrf_psi", psi);
        o.positive("mrf_weight", options.mrf.unary_weight);
        bool flag = false;
        if (o.get("no_vector", flag)) run->floorplan_files = !flag;
        if (o.get("keep_unfitted_glass", flag)) options.prune_unfitted_glass = !flag;
        if (o.get("sparse_panes", flag)) options.sparse_panes = flag;
        if (o.get("keep_opaque_glass", flag)) options.opaque_glass = !flag;
        if (o.get("keep_phantoms", flag)) options.phantoms = !flag;
        if (o.get("no_scan_fit", flag)) options.scan_fit.enabled = !flag;
        if (o.get("no_scan_clutter", flag)) options.scan_clutter.enabled = !flag;
        o.range("clutter_min_share", options.scan_clutter.min_share, 1e-6, 1.0);
        o.range("phantom_fraction", options.phantom.min_folded_fraction, 0.0, 1.0);
        o.positive("phantom_margin", options.phantom.block_margin);
        o.positive("resolution", mp.resolution);
        double max_memory_mb = 4096.0;
        o.positive("max_memory", max_memory_mb);
        o.get("angle_bin", mp.angle_bin_deg);
        o.positive("range_cap", mp.beams.range_cap);
        o.get("no_return_range", mp.beams.no_return_range);
        o.get("miss_margin", mp.beams.miss_margin);
        int laser_id = 0;
        o.get("laser_id", laser_id);
        o.get("sigmoid_margin", mp.direct.sigmoid_margin);
        o.get("direct_sigma", mp.direct.direct_sigma_deg);
        o.get("direct_peak", mp.direct.direct_peak);
        o.get("prior_glass", mp.direct.prior_glass);
        o.get("prior_occupied", mp.direct.prior_occupied);
        o.get("p_hit_empty", mp.direct.p_hit_emp);
        o.get("p_hit_empty_from_log", mp.direct.p_hit_emp_from_log);
        o.get("p_hit_occupied", mp.direct.p_hit_occ);
        o.get("min_glass_hits", mp.direct.min_glass_hits);
        o.get("heuristic_min_hits", mp.heuristic.min_hits);
        o.get("heuristic_min_misses", mp.heuristic.min_other_misses);
        if (const py::object s = o.take("sensor")) options.sensor = profileFrom(s, "map_log(): option 'sensor'");
        const py::object spool_dir = o.take("spool_dir");
        if (o.get("no_calibrate", flag)) options.calibrate = !flag;
        o.get("profile_lobe", options.profile_lobe);
        o.get("lobe_search", options.lobe_search);
        o.range("calibration_rounds", options.calibration_rounds, 1, 5);
        o.finish();
        if (laser_id != 0 && py::isinstance<Log>(log_or_path))
          throw py::value_error("map_log(): option 'laser_id' applies to a log read from a path; pass it to read_log");

        LogReadOptions read;
        read.carmen.laser_id = laser_id;
        read.carmen.max_memory_bytes = static_cast<std::size_t>(max_memory_mb * 1e6);  // the log counts too
        // A log read here over a quarter of the budget is kept on disk, as `glassmap map` does.
        read.carmen.spool_above_bytes = read.carmen.max_memory_bytes / 4;
        read.carmen.spool_directory =
            spool_dir ? toPath(spool_dir, "map_log(): option 'spool_dir'") : std::filesystem::temp_directory_path();
        // Names are parsed here, at the edge, as the command line does.
        options.method = pipeline::parseMapMethod(method);
        options.mrf.solver = mrf::parseSolver(solver);
        options.mrf.psi = mrf::parsePsi(psi);
        const std::shared_ptr<Log> log = logFrom(log_or_path, read, "map_log(log)", max_memory_mb);
        const double seconds_read = secondsSince(t0);
        options.mapping.max_memory_bytes =
            pipeline::gridMemoryBudget(static_cast<std::size_t>(max_memory_mb * 1e6), log->log);
        options.fit_floorplan = run->floorplan_files;
        {
          py::gil_scoped_release release;
          run->result = pipeline::mapLog(log->log, options);
        }
        run->info.log = log->path;
        run->info.seconds_read = seconds_read;
        run->info.seconds_total = secondsSince(t0);
        run->info.peak_memory_bytes = pipeline::peakMemoryBytes();
        run->info.log_on_disk_bytes = pipeline::logOnDiskBytes(log->log);
        return run;
      },
      py::arg("log"),
      "Maps a laser log (a Log or a path) as `glassmap map` does, with the same defaults; options are\n"
      "its long options with underscores: method ('heuristic', 'direct', 'mrf'), mrf_solver, mrf_psi,\n"
      "mrf_weight, no_vector, keep_unfitted_glass, sparse_panes, keep_opaque_glass, keep_phantoms,\n"
      "no_scan_fit, no_scan_clutter, clutter_min_share, phantom_fraction, phantom_margin,\n"
      "resolution [m], max_memory [MB], angle_bin [deg], range_cap, no_return_range, miss_margin [m],\n"
      "laser_id, sigmoid_margin, direct_sigma, direct_peak, prior_glass, prior_occupied, p_hit_empty,\n"
      "p_hit_empty_from_log, p_hit_occupied, min_glass_hits, heuristic_min_hits, heuristic_min_misses, sensor (a "
      "profile\n"
      "file or dict), no_calibrate, profile_lobe, lobe_search, calibration_rounds, spool_dir (where a log read from a\n"
      "path whose scans need more than a quarter of max_memory is kept, in an unnamed temporary file;\n"
      "default: the system's temporary folder, TMPDIR). Returns a MapResult.");
}

}  // namespace glassmap::python
