#include "glassmap/io/sensor_profile.hpp"

#include <cairo.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <utility>

#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

// Every estimated field with its key and its plausible range.
struct Field {
  const char* key;
  Estimate SensorProfile::*member;
  double lo, hi;
  const char* unit;
};

constexpr Field kFields[] = {
    {"range_sigma_m", &SensorProfile::range_sigma_m, 1e-5, 5.0, "m"},
    {"range_sigma_rel", &SensorProfile::range_sigma_rel, 0.0, 0.2, ""},
    {"w_hit", &SensorProfile::w_hit, 0.0, 1.0, ""},
    {"w_short", &SensorProfile::w_short, 0.0, 1.0, ""},
    {"w_max", &SensorProfile::w_max, 0.0, 1.0, ""},
    {"w_rand", &SensorProfile::w_rand, 0.0, 1.0, ""},
    {"lambda_short", &SensorProfile::lambda_short, 1e-6, 100.0, "1/m"},
    {"direct_peak", &SensorProfile::direct_peak, 0.0, 1.0, ""},
    {"direct_sigma_deg", &SensorProfile::direct_sigma_deg, 0.05, 90.0, "deg"},
    {"direct_floor", &SensorProfile::direct_floor, 0.0, 1.0, ""},
    {"normal_lambda_per_deg", &SensorProfile::normal_lambda_per_deg, 0.0, 10.0, "1/deg"},
    {"normal_floor", &SensorProfile::normal_floor, 0.0, 1.0, ""},
    {"glass_offset_m", &SensorProfile::glass_offset_m, -1.0, 1.0, "m"},
};

}  // namespace

void writeSensorProfile(const fs::path& path, const SensorProfile& p) {
  YAML::Emitter out;
  out << YAML::Comment("glassmap sensor profile (see glassmap calibrate --help)");
  out << YAML::BeginMap;
  out << YAML::Key << "source" << YAML::Value << p.source;
  out << YAML::Key << "max_range" << YAML::Value << p.max_range;
  out << YAML::Key << "typical_range_m" << YAML::Value << p.typical_range_m;
  out << YAML::Key << "wall_beams" << YAML::Value << p.wall_beams;
  out << YAML::Key << "glass_beams" << YAML::Value << p.glass_beams;
  YAML::Node fitted(YAML::NodeType::Sequence);
  for (const Field& f : kFields) {
    const Estimate& e = p.*f.member;
    out << YAML::Key << f.key << YAML::Value << e.value;
    if (e.fitted) out << YAML::Key << std::string(f.key) + "_se" << YAML::Value << e.se;
  }
  out << YAML::Key << "fitted" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const Field& f : kFields)
    if ((p.*f.member).fitted) out << f.key;
  out << YAML::EndSeq << YAML::EndMap;
  if (!out.good()) throw Error("cannot format the sensor profile: " + out.GetLastError(), path.string());
  writeAtomically(path, [&](const fs::path& tmp) {
    std::ofstream f(tmp);
    f << out.c_str() << "\n";
    if (!f.flush()) throw Error("cannot write", tmp.string());
  });
}

SensorProfile readSensorProfile(const fs::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error("sensor profile does not exist", name);
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(name);
  } catch (const YAML::Exception& e) {
    throw Error("bad YAML: " + e.msg, name, e.mark.is_null() ? 0 : static_cast<std::size_t>(e.mark.line + 1));
  }
  if (!doc.IsMap()) throw Error("a sensor profile must be a mapping of keys", name, 1);
  SensorProfile p;
  p.source = name;
  auto line = [](const YAML::Node& n) { return n.Mark().is_null() ? 0 : static_cast<std::size_t>(n.Mark().line + 1); };
  auto number = [&](const YAML::Node& n, const char* key) {
    try {
      const double v = n.as<double>();
      if (!std::isfinite(v)) throw Error("not a finite number", name, line(n), key);
      return v;
    } catch (const YAML::Exception&) {
      throw Error("expected a number", name, line(n), key);
    }
  };
  for (const Field& f : kFields) {
    const YAML::Node n = doc[f.key];
    if (!n) continue;
    const double v = number(n, f.key);
    if (v < f.lo || v > f.hi) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "%g %s is implausible (expected %g to %g)", v, f.unit, f.lo, f.hi);
      throw Error(buf, name, line(n), f.key);
    }
    Estimate& e = p.*f.member;
    e.value = v;
    if (const YAML::Node se = doc[std::string(f.key) + "_se"]) e.se = number(se, f.key);
  }
  if (const YAML::Node fitted = doc["fitted"]; fitted && fitted.IsSequence())
    for (const YAML::Node& k : fitted)
      for (const Field& f : kFields)
        if (k.Scalar() == f.key) (p.*f.member).fitted = true;
  if (const YAML::Node n = doc["max_range"]) p.max_range = number(n, "max_range");
  if (const YAML::Node n = doc["typical_range_m"]) p.typical_range_m = std::max(0.0, number(n, "typical_range_m"));
  if (const YAML::Node n = doc["source"]) p.source = n.Scalar();
  if (p.direct_floor.value > p.direct_peak.value)
    throw Error("direct_floor above direct_peak", name, line(doc["direct_floor"]), "direct_floor");
  const double w = p.w_hit.value + p.w_short.value + p.w_max.value + p.w_rand.value;
  if (!(w > 0)) throw Error("the mixture weights w_hit, w_short, w_max, w_rand sum to 0", name, 0, "w_hit");
  return p;
}

void renderCalibrationChart(const fs::path& path, const SensorProfile& p, const std::vector<GlassAngleBin>& bins) {
  constexpr int kW = 720, kH = 440, kLeft = 60, kRight = 20, kTop = 36, kBottom = 50;
  const double pw = kW - kLeft - kRight, ph = kH - kTop - kBottom;
  auto X = [&](double theta) { return kLeft + pw * theta / 90.0; };
  auto Y = [&](double frac) { return kTop + ph * (1.0 - frac); };
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, kW, kH), cairo_surface_destroy);
  std::unique_ptr<cairo_t, decltype(&cairo_destroy)> cr_guard(cairo_create(surface.get()), cairo_destroy);
  cairo_t* cr = cr_guard.get();
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 11);
  // Axes and grid.
  cairo_set_line_width(cr, 1);
  for (int t = 0; t <= 90; t += 10) {
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, X(t), Y(0));
    cairo_line_to(cr, X(t), Y(1));
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_move_to(cr, X(t) - 6, Y(0) + 14);
    cairo_show_text(cr, std::to_string(t).c_str());
  }
  for (int k = 0; k <= 10; k += 2) {
    const double f = k / 10.0;
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, X(0), Y(f));
    cairo_line_to(cr, X(90), Y(f));
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    char buf[16];
    std::snprintf(buf, sizeof buf, "%.1f", f);
    cairo_move_to(cr, kLeft - 28, Y(f) + 4);
    cairo_show_text(cr, buf);
  }
  cairo_move_to(cr, kLeft + pw / 2 - 80, kH - 14);
  cairo_show_text(cr, "incidence angle on the pane [deg]");
  char title[200];
  std::snprintf(title, sizeof title,
                "direct return: peak %.2f, sigma %.1f deg, floor %.3f;  reflected: lambda %.3f/deg, floor %.2f",
                p.direct_peak.value, p.direct_sigma_deg.value, p.direct_floor.value, p.normal_lambda_per_deg.value,
                p.normal_floor.value);
  cairo_move_to(cr, kLeft, 20);
  cairo_show_text(cr, title);
  // Measured fractions with a Wilson 95% interval, then the fitted curves.
  for (int series = 0; series < 2; ++series) {
    const double r = series == 0 ? 0.1 : 0.85, g = series == 0 ? 0.35 : 0.45,
                 b = series == 0 ? 0.8 : 0.1;  // blue, orange
    cairo_set_source_rgb(cr, r, g, b);
    for (const GlassAngleBin& bin : bins) {
      const double n = static_cast<double>(series == 0 ? bin.beams : bin.mirror_beams);
      const double k = static_cast<double>(series == 0 ? bin.direct : bin.reflected);
      if (n < 5) continue;
      const double f = k / n, z = 1.96, den = 1 + z * z / n;
      const double centre = (f + z * z / (2 * n)) / den;
      const double half = z * std::sqrt(f * (1 - f) / n + z * z / (4 * n * n)) / den;
      const double x = X(0.5 * (bin.theta_lo + bin.theta_hi));
      cairo_move_to(cr, x, Y(std::max(0.0, centre - half)));
      cairo_line_to(cr, x, Y(std::min(1.0, centre + half)));
      cairo_stroke(cr);
      cairo_arc(cr, x, Y(f), 3, 0, 2 * 3.14159265358979);
      cairo_fill(cr);
    }
    cairo_set_line_width(cr, 2);
    for (int i = 0; i <= 900; ++i) {
      const double theta = i / 10.0;
      const double v = series == 0 ? directProbability(p, theta) : reflectedProbability(p, theta);
      if (i == 0)
        cairo_move_to(cr, X(theta), Y(std::clamp(v, 0.0, 1.0)));
      else
        cairo_line_to(cr, X(theta), Y(std::clamp(v, 0.0, 1.0)));
    }
    cairo_stroke(cr);
    cairo_set_line_width(cr, 1);
    cairo_move_to(cr, X(62), Y(0.92) + 16 * series);
    cairo_show_text(cr, series == 0 ? "direct return (dots: measured)" : "reflected, given no direct return");
  }
  cr_guard.reset();
  writeAtomically(path, [&](const fs::path& tmp) {
    if (cairo_surface_write_to_png(surface.get(), tmp.c_str()) != CAIRO_STATUS_SUCCESS)
      throw Error("cannot write PNG", path.string());
  });
}

}  // namespace glassmap
