// localize and calibrate: `glassmap localize` and `glassmap calibrate` as functions.
#include <chrono>

#include "common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/sensor_profile.hpp"
#include "glassmap/io/tum.hpp"
#include "glassmap/pipeline/localize_checks.hpp"
#include "glassmap/pipeline/localize_log.hpp"

namespace glassmap::python {
namespace {

/// What localize returns.
struct LocalizeRun {
  pipeline::LocalizeResult result;
  nlohmann::json summary;
};

// A floorplan argument given as a path is read as read_floorplan reads it, with `units`/`layers`.
Floorplan planFrom(const py::object& obj, const py::object& units, const py::object& layers, const std::string& what) {
  if (!isPathLike(obj)) {
    if (!units.is_none() || !layers.is_none())
      throw py::value_error(what + ": units and layers apply to a floorplan read from a path");
    return floorplanFrom(obj, what);
  }
  return py::module_::import("glassmap._glassmap").attr("read_floorplan")(obj, units, layers).cast<Floorplan>();
}

py::array_t<double> column(const std::vector<double>& v) {
  py::array_t<double> out(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}

}  // namespace

void bindLocalize(py::module_& m) {
  py::class_<LocalizeRun>(m, "LocalizeResult", "What localize made of a log.")
      .def_property_readonly(
          "poses",
          [](const LocalizeRun& r) {
            const auto& t = r.result.run.trajectory;
            py::array_t<double> out({static_cast<py::ssize_t>(t.size()), py::ssize_t{3}});
            auto a = out.mutable_unchecked<2>();
            for (std::size_t i = 0; i < t.size(); ++i) {
              const auto row = static_cast<py::ssize_t>(i);
              a(row, 0) = t[i].pose.x();
              a(row, 1) = t[i].pose.y();
              a(row, 2) = t[i].pose.theta;
            }
            return out;
          },
          "estimated laser pose T_map_laser per scan (N x 3: x, y, theta)")
      .def_property_readonly(
          "times",
          [](const LocalizeRun& r) {
            std::vector<double> t;
            for (const StampedPose& p : r.result.run.trajectory) t.push_back(p.timestamp);
            return column(t);
          },
          "scan timestamps [s] (N)")
      .def_property_readonly(
          "spread", [](const LocalizeRun& r) { return column(r.result.run.spread); },
          "particle spread per scan: weighted RMS distance of the particles from the estimate [m] (N)")
      .def_property_readonly(
          "particles", [](const LocalizeRun& r) { return r.result.run.particles; }, "particle count per scan")
      .def_property_readonly(
          "corrected",
          [](const LocalizeRun& r) {
            return std::vector<bool>(r.result.run.corrected.begin(), r.result.run.corrected.end());
          },
          "per scan: True when it was a measurement update")
      .def_property_readonly(
          "settled",
          [](const LocalizeRun& r) {
            return std::vector<bool>(r.result.run.settled.begin(), r.result.run.settled.end());
          },
          "per scan: True when the cloud is one tight mode from this scan to the end (--spread's converged)")
      .def_property_readonly(
          "converged", [](const LocalizeRun& r) { return r.result.run.converged; },
          "the cloud ends as one tight mode: the estimate can be trusted")
      .def_property_readonly(
          "summary", [](const LocalizeRun& r) { return toPython(r.summary); },
          "the run's summary: the content of `glassmap localize --json`")
      .def(
          "write_tum",
          [](const LocalizeRun& r, const py::object& path) {
            writeTum(toPath(path, "write_tum(path)"), r.result.run.trajectory);
          },
          py::arg("path"), "writes the trajectory as TUM, as `glassmap localize -o` does")
      .def(
          "write_spread",
          [](const LocalizeRun& r, const py::object& path) {
            localize::writeSpreadCsv(toPath(path, "write_spread(path)"), r.result.run);
          },
          py::arg("path"), "writes the particle spread per scan as CSV, as `glassmap localize --spread` does")
      .def("__len__", [](const LocalizeRun& r) { return r.result.run.trajectory.size(); })
      .def("__repr__", [](const LocalizeRun& r) {
        return "<glassmap.LocalizeResult model=" + r.result.model + " scans=" + std::to_string(r.result.run.scans) +
               " converged=" + (r.result.run.converged ? "True" : "False") + ">";
      });

  m.def(
      "localize",
      [](const py::object& floorplan, const py::object& log_or_path, const py::object& init, const py::kwargs& kwargs) {
        Options o("localize", kwargs);
        py::object units = o.take("units"), layers = o.take("layers");
        if (!units) units = py::none();
        if (!layers) layers = py::none();
        pipeline::LocalizeOptions options;
        std::string glass_as = "opaque";
        o.get("model", options.model);
        o.get("glass_as", glass_as);
        localize::LocalizeOptions& opt = options.filter;
        o.get("particles", opt.filter.max_particles);
        o.get("min_particles", opt.filter.min_particles);
        bool flag = false;
        if (o.get("fixed_count", flag)) opt.filter.adaptive = !flag;
        o.get("beams", opt.beams);
        if (const py::object off = o.take("laser_offset"))
          opt.T_base_laser = poseFrom(off, "localize(): option 'laser_offset'");
        double sigma_hit = sensor::SensorParams{}.sigma_hit;
        const bool sigma_hit_given = o.positive("sigma_hit", sigma_hit);
        const py::object sensor = o.take("sensor");
        o.get("global_temperature", opt.filter.global_temperature);
        bool no_inject = false, inject_always = false;
        o.get("no_inject", no_inject);
        o.range("lost_share", opt.filter.contradiction_share, 0.0, 1.0);
        o.get("inject_always", inject_always);
        if (no_inject && inject_always)
          throw py::value_error("localize(): options 'no_inject' and 'inject_always' exclude each other");
        opt.filter.recovery = no_inject       ? localize::Recovery::None
                              : inject_always ? localize::Recovery::Inject
                                              : localize::Recovery::Probe;
        bool no_self_calibrate = false;
        o.get("no_self_calibrate", no_self_calibrate);
        o.get("seed", opt.filter.seed);
        o.finish();

        const Floorplan plan = planFrom(floorplan, units, layers, "localize(floorplan)");
        // A plan read with its units given explicitly, or given here, only warns (it did when read).
        pipeline::checkLocalizationPlan(plan.map, plan.path, plan.scale_warning, plan.units_given);
        LogReadOptions read;
        read.ros2.pose_source = BagPoseSource::Odometry;  // localization uses odometry alone
        const std::shared_ptr<Log> log = logFrom(log_or_path, read, "localize(log)");
        if (log->log.scans.empty()) throw Error("the log holds no scan", log->path);

        options.sensor.glass_as = sensor::parseGlassAs(glass_as);
        options.sensor.sigma_hit = sigma_hit;
        if (sensor) {
          options.sensor =
              sensor::paramsFromProfile(profileFrom(sensor, "localize(): option 'sensor'"), options.sensor);
          if (sigma_hit_given) {  // an explicit option wins: one sigma for every beam
            options.sensor.sigma_hit = sigma_hit;
            options.sensor.sigma_hit_rel = 0.0;
          }
        }
        opt.self_calibration.enabled = !sensor && !no_self_calibrate;  // as the command line
        if (!init.is_none()) {
          opt.init = poseFrom(init, "localize(init)");
          pipeline::checkInitialPose(plan.map, *opt.init, plan.path);
        }
        LocalizeRun run;
        {
          py::gil_scoped_release release;
          run.result = pipeline::localizeLog(log->log, plan.map, options);
        }
        run.summary = pipeline::localizeSummaryJson(run.result, options);
        return run;
      },
      py::arg("floorplan"), py::arg("log"), py::arg("init") = py::none(),
      "Monte Carlo localization of a log (a Log or a path) against a floorplan (a Floorplan, a map_log\n"
      "result, a list of Segments or a path) as `glassmap localize` does, with the same defaults; init =\n"
      "(x, y, theta) of the laser, None = global localization. Options are its long options with\n"
      "underscores: model ('glass', 'glass-paper', 'beam', 'field'), glass_as ('opaque', 'invisible'),\n"
      "particles, min_particles, fixed_count, beams, laser_offset (x, y, theta), units, layers,\n"
      "sigma_hit [m], sensor (a profile file or dict), global_temperature, no_inject, lost_share,\n"
      "inject_always, no_self_calibrate, seed. Returns a LocalizeResult (poses N x 3, spread, summary, ...).");

  m.def(
      "calibrate",
      [](const py::object& log_or_path, const py::object& floorplan, const py::kwargs& kwargs) {
        const auto t0 = std::chrono::steady_clock::now();
        Options o("calibrate", kwargs);
        py::object units = o.take("units"), layers = o.take("layers");
        if (!units) units = py::none();
        if (!layers) layers = py::none();
        pipeline::MapOptions options;
        std::size_t max_scans = options.calibration.max_scans;
        if (o.get("max_scans", max_scans)) {
          if (max_scans == 0) throw py::value_error("calibrate(): option 'max_scans' must be positive");
          options.calibration.max_scans = max_scans;
        }
        std::string sigma_from;
        if (o.get("sigma_from", sigma_from)) {
          if (sigma_from != "walls" && sigma_from != "scan")
            throw py::value_error("calibrate(): option 'sigma_from' must be walls or scan, got '" + sigma_from + "'");
          options.calibration.sigma_source =
              sigma_from == "scan" ? sensor::SigmaSource::Local : sensor::SigmaSource::Walls;
        }
        bool flag = false;
        if (o.get("no_align", flag)) options.calibration.align_scans = !flag;
        o.get("min_glass_beams", options.calibration.min_glass_beams);
        o.range("rounds", options.calibration_rounds, 1, 5);
        o.positive("resolution", options.mapping.resolution);
        o.get("no_return_range", options.mapping.beams.no_return_range);
        int laser_id = 0;
        o.get("laser_id", laser_id);
        o.finish();
        if (laser_id != 0 && py::isinstance<Log>(log_or_path))
          throw py::value_error(
              "calibrate(): option 'laser_id' applies to a log read from a path; pass it to read_log");

        LogReadOptions read;
        read.carmen.laser_id = laser_id;
        const std::shared_ptr<Log> log = logFrom(log_or_path, read, "calibrate(log)");
        Floorplan plan;
        const bool has_plan = !floorplan.is_none();
        if (has_plan)
          plan = planFrom(floorplan, units, layers, "calibrate(floorplan)");
        else if (!units.is_none() || !layers.is_none())
          throw py::value_error("calibrate(): units and layers apply to a floorplan");
        pipeline::CalibrateLogResult r;
        {
          py::gil_scoped_release release;
          r = pipeline::calibrateLog(log->log, has_plan ? &plan.map : nullptr, options);
        }
        SensorProfile profile = r.fit.profile;
        const std::string plan_name = has_plan ? (plan.path.empty() ? std::string("floorplan") : plan.path) : "";
        profile.source = pipeline::calibrationSource(log->path, plan_name);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const nlohmann::json j = pipeline::calibrationJson(profile, r, log->path, plan_name, seconds);
        py::object out = toPython(j);
        for (const std::string& w : r.fit.warnings)
          if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
        return out;
      },
      py::arg("log"), py::arg("floorplan") = py::none(),
      "The sensor profile of a log's laser (a Log or a path) as `glassmap calibrate` fits it: against a\n"
      "floorplan (a Floorplan, list of Segments or a path) or, without one, against the log's own map.\n"
      "Options are its long options with underscores: max_scans, sigma_from ('walls', 'scan'), no_align,\n"
      "min_glass_beams, rounds, resolution, no_return_range, laser_id, units, layers. Returns the dict of\n"
      "`glassmap calibrate --json` (the profile's keys, the fit's figures); write it with\n"
      "write_sensor_profile.");
}

}  // namespace glassmap::python
