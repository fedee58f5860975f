// The Python module glassmap._glassmap: the pipeline of the glassmap command as functions.
#include <new>

#include "common.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap::python {

Options::Options(std::string function, const py::kwargs& kwargs) : function_(std::move(function)), kwargs_(kwargs) {}

py::object Options::take(const char* name) {
  taken_.insert(name);
  if (!kwargs_.contains(name)) return {};
  py::object v = kwargs_[name];
  if (v.is_none()) return {};
  return v;
}

bool Options::positive(const char* name, double& out) {
  double v = 0.0;
  if (!get(name, v)) return false;
  if (!(v > 0.0))
    throw py::value_error(function_ + "(): option '" + name + "' must be positive, got " + std::to_string(v));
  out = v;
  return true;
}

void Options::finish() const {
  for (const auto& item : kwargs_) {
    const std::string key = py::str(item.first);
    if (taken_.count(key) == 0) {
      std::string known;
      for (const std::string& k : taken_) known += (known.empty() ? "" : ", ") + k;
      throw py::type_error(function_ + "() got an unexpected keyword argument '" + key + "' (options: " + known + ")");
    }
  }
}

bool isPathLike(const py::handle& obj) {
  return py::isinstance<py::str>(obj) || py::isinstance<py::bytes>(obj) || py::hasattr(obj, "__fspath__");
}

std::filesystem::path toPath(const py::handle& obj, const std::string& what) {
  if (!isPathLike(obj))
    throw py::type_error(what + ": expected a path (str or os.PathLike), got " +
                         std::string(py::str(py::type::of(obj).attr("__name__"))));
  return obj.cast<std::filesystem::path>();
}

py::object toPython(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

nlohmann::json toJson(const py::handle& obj) {
  const std::string text = py::str(py::module_::import("json").attr("dumps")(obj));
  return nlohmann::json::parse(text);
}

Pose2 poseFrom(const py::handle& obj, const std::string& what) {
  std::vector<double> v;
  try {
    if (isPathLike(obj)) throw py::cast_error();
    v = obj.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    throw py::type_error(what + ": expected (x, y, theta) [m, m, rad]");
  }
  if (v.size() != 3)
    throw py::type_error(what + ": expected (x, y, theta) [m, m, rad], got " + std::to_string(v.size()) + " numbers");
  return {v[0], v[1], v[2]};
}

py::tuple poseTuple(const Pose2& p) { return py::make_tuple(p.x(), p.y(), p.theta); }

void bindErrors(py::module_& m) {
  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  error.doc() =
      "An error of the glassmap pipeline (bad input, bad option, a file that cannot be read or written).\n"
      "str(e) is the message the command line prints; e.file, e.line and e.field say where, when known.";
  py::register_exception_translator([](std::exception_ptr p) {
    auto raise = [](const std::string& what, const std::string& file, std::size_t line, const std::string& field) {
      py::object inst = py::reinterpret_borrow<py::object>(error.ptr())(what);
      inst.attr("file") = file.empty() ? py::object(py::none()) : py::object(py::str(file));
      inst.attr("line") = line == 0 ? py::object(py::none()) : py::object(py::int_(line));
      inst.attr("field") = field.empty() ? py::object(py::none()) : py::object(py::str(field));
      PyErr_SetObject(error.ptr(), inst.ptr());
    };
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      raise(e.what(), e.file(), e.line(), e.field());
    } catch (const py::builtin_exception&) {
      throw;  // TypeError, ValueError, ... of the bindings: pybind11 translates them
    } catch (const py::error_already_set&) {
      throw;
    } catch (const std::bad_alloc&) {
      raise(
          "out of memory: the input asks for more than this machine can give; see max_memory or check the "
          "input for coordinates far from the rest",
          {}, 0, {});
    } catch (const std::exception& e) {
      raise(e.what(), {}, 0, {});
    }
  });
}

}  // namespace glassmap::python

PYBIND11_MODULE(_glassmap, m) {
  namespace gp = glassmap::python;
  m.doc() = "glassmap: glass-aware laser mapping, vector floorplans and localization (the C++ pipeline)";
  gp::bindErrors(m);
  gp::bindLog(m);
  gp::bindFloorplan(m);
  gp::bindMap(m);
  gp::bindLocalize(m);
}
