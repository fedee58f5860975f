#pragma once
// Shared parts of the Python module: the objects it wraps, keyword options, JSON <-> Python.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/core/sensor_profile.hpp"
#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/io/log.hpp"
#include "glassmap/pipeline/map_log.hpp"
#include "glassmap/pipeline/reports.hpp"

namespace glassmap::python {

namespace py = pybind11;

/// A log read by read_log, with where it came from.
struct Log {
  LaserLog log;
  std::string path;  ///< as given to read_log ("" for a log made in Python)
  LogReadNotes notes;
};

/// A floorplan with how it was read.
struct Floorplan {
  VectorMap map;
  std::string path;           ///< "" for a floorplan made in Python or by map_log
  std::string scale_warning;  ///< the implausible-extent warning, "" when plausible
  bool units_given = false;   ///< read with explicit units
  std::string units;          ///< where the units came from ("none declared: metres", ...)
  std::string report;         ///< what was read as what (per CAD layer), as the command line prints it
};

/// What map_log returns: the pipeline's result, the options it ran with and the run's figures.
struct MapRun {
  pipeline::MapResult result;
  pipeline::MapOptions options;
  pipeline::MapRunInfo info;
  bool floorplan_files = true;  ///< write() writes the floorplan files (no_vector not given)
};

/// Keyword options of one call: take them one by one, then finish() refuses the rest.
class Options {
 public:
  Options(std::string function, const py::kwargs& kwargs);
  /// Sets `out` from option `name` when given (and not None); TypeError for a wrong type.
  template <class T>
  bool get(const char* name, T& out) {
    const py::object v = take(name);
    if (!v) return false;
    try {
      out = v.cast<T>();
    } catch (const py::cast_error&) {
      throw py::type_error(function_ + "(): option '" + name + "' has the wrong type " +
                           std::string(py::str(py::type::of(v).attr("__name__"))));
    }
    return true;
  }
  /// get() of a number that must be > 0 (ValueError otherwise).
  bool positive(const char* name, double& out);
  /// get() of a number that must lie in [lo, hi] (ValueError otherwise).
  template <class T>
  bool range(const char* name, T& out, T lo, T hi) {
    T v{};
    if (!get(name, v)) return false;
    if (!(v >= lo && v <= hi))
      throw py::value_error(function_ + "(): option '" + name + "' must lie in [" + std::to_string(lo) + ", " +
                            std::to_string(hi) + "], got " + std::to_string(v));
    out = v;
    return true;
  }
  /// The raw value of an option (null handle when absent or None); counts as taken.
  py::object take(const char* name);
  /// TypeError naming the first option not taken.
  void finish() const;
  const std::string& function() const { return function_; }

 private:
  std::string function_;
  py::dict kwargs_;
  std::set<std::string> taken_;
};

/// A str or os.PathLike as a path; TypeError naming `what` otherwise.
std::filesystem::path toPath(const py::handle& obj, const std::string& what);
/// True for str, bytes and os.PathLike objects.
bool isPathLike(const py::handle& obj);

/// JSON as Python objects (dict, list, ...), and back.
py::object toPython(const nlohmann::json& j);
nlohmann::json toJson(const py::handle& obj);

/// The log argument of map_log/localize/calibrate: a Log, or a path read with `read` (with
/// max_memory_mb > 0, a read stopped by the memory limit says to raise max_memory).
std::shared_ptr<Log> logFrom(const py::object& obj, const LogReadOptions& read, const std::string& what,
                             double max_memory_mb = 0.0);

/// A sensor profile from a path (YAML) or a dict (profile JSON); named `option` in errors.
SensorProfile profileFrom(const py::handle& obj, const std::string& option);

/// A floorplan argument: a Floorplan, a MapResult (its floorplan), or a sequence of Segments.
Floorplan floorplanFrom(const py::handle& obj, const std::string& what);

/// (x, y, theta) from a sequence of three numbers; TypeError naming `what` otherwise.
Pose2 poseFrom(const py::handle& obj, const std::string& what);
py::tuple poseTuple(const Pose2& p);

/// Registrations of each part of the module.
void bindErrors(py::module_& m);
void bindLog(py::module_& m);
void bindFloorplan(py::module_& m);
void bindMap(py::module_& m);
void bindLocalize(py::module_& m);

}  // namespace glassmap::python
