// Floorplans (Segment, Floorplan, read_floorplan, write_floorplan) and sensor profiles.
#include <pybind11/operators.h>

#include "common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/sensor_profile.hpp"
#include "glassmap/vector/export.hpp"

namespace glassmap::python {
namespace {

Vec2 pointFrom(const py::handle& obj, const char* what) {
  std::vector<double> v;
  try {
    v = obj.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    throw py::type_error(std::string("Segment.") + what + ": expected (x, y) [m]");
  }
  if (v.size() != 2) throw py::type_error(std::string("Segment.") + what + ": expected (x, y) [m]");
  return {v[0], v[1]};
}

py::tuple pointTuple(const Vec2& p) { return py::make_tuple(p.x(), p.y()); }

// Keys of calibrate()'s report that are not profile keys: write_sensor_profile takes its dict as is.
const std::vector<std::string>& reportKeys() {
  static const std::vector<std::string> keys = {"log",
                                                "floorplan",
                                                "own_floorplan",
                                                "floorplan_walls",
                                                "floorplan_panes",
                                                "rounds",
                                                "scans_used",
                                                "aligned_scans",
                                                "median_alignment_m",
                                                "median_alignment_deg",
                                                "refracted_beams",
                                                "transient_panes",
                                                "transient_length_m",
                                                "range_sigma_walls_m",
                                                "range_sigma_in_scan_m",
                                                "angle_bins",
                                                "warnings",
                                                "seconds"};
  return keys;
}

}  // namespace

SensorProfile profileFrom(const py::handle& obj, const std::string& option) {
  if (isPathLike(obj)) return readSensorProfile(toPath(obj, option));
  if (py::isinstance<py::dict>(obj)) return pipeline::profileFromJson(toJson(obj), reportKeys());
  throw py::type_error(option + ": expected a sensor profile file (path) or dict");
}

Floorplan floorplanFrom(const py::handle& obj, const std::string& what) {
  if (py::isinstance<Floorplan>(obj)) return obj.cast<const Floorplan&>();
  if (py::isinstance<MapRun>(obj)) {
    Floorplan f;
    f.map = obj.cast<const MapRun&>().result.floorplan.map;
    return f;
  }
  if (isPathLike(obj) || !py::isinstance<py::iterable>(obj))
    throw py::type_error(what + ": expected a Floorplan, a map_log result or a list of Segments");
  Floorplan f;
  for (const py::handle item : obj) {
    if (!py::isinstance<MapSegment>(item)) throw py::type_error(what + ": expected Segments in the list");
    f.map.segments.push_back(item.cast<const MapSegment&>());
  }
  return f;
}

void bindFloorplan(py::module_& m) {
  py::class_<MapSegment>(m, "Segment", "A straight piece of wall or glass; endpoints in the map frame [m].")
      .def(py::init([](const py::object& a, const py::object& b, const std::string& material, double thickness) {
             MapSegment s;
             s.a = pointFrom(a, "a");
             s.b = pointFrom(b, "b");
             s.material = parseMaterial(material);
             s.thickness = thickness;
             return s;
           }),
           py::arg("a"), py::arg("b"), py::arg("material") = "wall", py::arg("thickness") = 0.1)
      .def_property(
          "a", [](const MapSegment& s) { return pointTuple(s.a); },
          [](MapSegment& s, const py::object& p) { s.a = pointFrom(p, "a"); }, "first endpoint (x, y) [m]")
      .def_property(
          "b", [](const MapSegment& s) { return pointTuple(s.b); },
          [](MapSegment& s, const py::object& p) { s.b = pointFrom(p, "b"); }, "second endpoint (x, y) [m]")
      .def_property(
          "material", [](const MapSegment& s) { return std::string(toString(s.material)); },
          [](MapSegment& s, const std::string& name) { s.material = parseMaterial(name); }, "'wall' or 'glass'")
      .def_readwrite("thickness", &MapSegment::thickness, "pane or wall thickness [m]")
      .def_readwrite("pane_angle", &MapSegment::pane_angle, "pane normal direction in [0, pi) [rad] (0: unknown)")
      .def_readwrite("support", &MapSegment::support, "supporting grid cells (0: unknown)")
      .def_readwrite("evidence", &MapSegment::evidence, "mean per-cell evidence (0: unknown)")
      .def_property_readonly("length", &MapSegment::length, "[m]")
      .def("__eq__",
           [](const MapSegment& x, const MapSegment& y) {
             return x.a == y.a && x.b == y.b && x.material == y.material && x.thickness == y.thickness;
           })
      .def("__repr__", [](const MapSegment& s) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "Segment((%.3f, %.3f), (%.3f, %.3f), '%s', thickness=%.3f)", s.a.x(), s.a.y(),
                      s.b.x(), s.b.y(), std::string(toString(s.material)).c_str(), s.thickness);
        return std::string(buf);
      });

  py::class_<Floorplan>(m, "Floorplan", "Wall and glass segments of one floor, in local metres.")
      .def(py::init([](const py::object& segments) {
             return segments.is_none() ? Floorplan{} : floorplanFrom(segments, "Floorplan(segments)");
           }),
           py::arg("segments") = py::none())
      .def_property(
          "segments", [](const Floorplan& f) { return f.map.segments; },
          [](Floorplan& f, const py::object& segments) { f.map = floorplanFrom(segments, "Floorplan.segments").map; },
          "the segments (a copy: assign a list to change them)")
      .def("__len__", [](const Floorplan& f) { return f.map.segments.size(); })
      .def(
          "count", [](const Floorplan& f, const std::string& material) { return f.map.count(parseMaterial(material)); },
          py::arg("material"), "number of 'wall' or 'glass' segments")
      .def_property_readonly(
          "bounds",
          [](const Floorplan& f) -> py::object {
            if (f.map.segments.empty()) return py::none();
            const auto box = f.map.bounds();
            return py::make_tuple(box.min().x(), box.min().y(), box.max().x(), box.max().y());
          },
          "(xmin, ymin, xmax, ymax) [m] of the segment ends, None when empty")
      .def_readonly("path", &Floorplan::path, "the file it was read from")
      .def_readonly("units", &Floorplan::units, "where the units came from")
      .def_readonly("report", &Floorplan::report, "what was read as what per CAD layer ('' when no layer decided)")
      .def_readonly("scale_warning", &Floorplan::scale_warning, "the implausible-extent warning, '' when plausible")
      .def("__repr__", [](const Floorplan& f) {
        return "<glassmap.Floorplan '" + f.path + "' walls=" + std::to_string(f.map.count(Material::Wall)) +
               " glass=" + std::to_string(f.map.count(Material::Glass)) + ">";
      });

  m.def(
      "read_floorplan",
      [](const py::object& path, const py::object& units, const py::object& layers, bool clutter) {
        Floorplan f;
        const std::filesystem::path p = toPath(path, "read_floorplan(path)");
        f.path = p.string();
        FloorplanUnits assumed;
        FloorplanReadReport report;
        FloorplanReadOptions read;
        read.units = &assumed;
        read.report = &report;
        read.clutter = clutter;
        if (!units.is_none()) {
          read.unit_in_metres = parseLengthUnit(std::string(py::str(units)), "units");
          f.units_given = true;
        }
        read.layer_rules = parseLayerRules(layers.is_none() ? std::string() : layers.cast<std::string>(), "layers");
        {
          py::gil_scoped_release release;
          f.map = readFloorplan(p, read);
        }
        if (report.by_layer_names || !report.notes.empty() || !report.warnings.empty())
          f.report = formatReadReport(report);
        f.units = assumed.source;
        f.scale_warning = implausibleExtentWarning(f.map, assumed, p);
        if (!f.scale_warning.empty() && PyErr_WarnEx(PyExc_UserWarning, f.scale_warning.c_str(), 1) != 0)
          throw py::error_already_set();
        return f;
      },
      py::arg("path"), py::arg("units") = py::none(), py::arg("layers") = py::none(), py::arg("clutter") = true,
      "Reads a floorplan (any OGR line source: GPKG, GeoJSON, DXF, Shapefile, FlatGeobuf) as the command line\n"
      "does. units: m, cm, mm, in, ft, us-ft, yd or metres per unit (default: the file's own); layers: CAD\n"
      "layer rules as --layers (\"glass=A-GLAZ*;wall=A-WALL*;ignore=A-FURN*\"); clutter: read the CLUTTER\n"
      "layer of a glassmap plan as walls (every surface a laser sees, as localize reads it), False: the\n"
      "building alone. A plan whose extent is implausible for a building warns (UserWarning) and\n"
      "localize() refuses it unless units were given.");

  m.def(
      "write_floorplan",
      [](const py::object& floorplan, const py::object& path) {
        const Floorplan f = floorplanFrom(floorplan, "write_floorplan(floorplan)");
        const std::filesystem::path p = toPath(path, "write_floorplan(path)");
        py::gil_scoped_release release;
        vector::exportFloorplan(p, f.map);
      },
      py::arg("floorplan"), py::arg("path"),
      "Writes a Floorplan, a map_log result's floorplan or a list of Segments in the format of the path's\n"
      "extension, as `glassmap export` does: .gpkg .geojson .json .shp .fgb .dxf .svg .png .pdf.");

  m.def(
      "read_sensor_profile",
      [](const py::object& path) { return toPython(pipeline::profileJson(readSensorProfile(toPath(path, "path")))); },
      py::arg("path"), "Reads a sensor profile (YAML) as a dict (the keys of `glassmap calibrate --json`).");
  m.def(
      "write_sensor_profile",
      [](const py::dict& profile, const py::object& path) {
        writeSensorProfile(toPath(path, "path"), profileFrom(profile, "profile"));
      },
      py::arg("profile"), py::arg("path"),
      "Writes a sensor profile dict (from calibrate() or read_sensor_profile(); any subset of the profile\n"
      "keys) as YAML, as `glassmap calibrate -o` does.");
}

}  // namespace glassmap::python
