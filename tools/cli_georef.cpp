#include "cli_georef.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <vector>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap::cli {

void addGeorefOptions(CLI::App& cmd, GeorefArgs& args, bool input) {
  cmd.add_option("--crs", args.crs,
                 "write the floorplan in the building's projected CRS (EPSG:N, WKT or PROJ; metres), e.g.\n"
                 "EPSG:25832; with --origin. GPKG/SHP/FGB carry it, GeoJSON names it, DXF holds building\n"
                 "coordinates; a GPKG (and our GeoJSON) records the map frame, so glassmap reads it back there");
  cmd.add_option("--origin", args.origin,
                 "where the map frame lies in --crs: E,N,ROT = easting and northing of the map origin [m] and\n"
                 "the map x axis' angle from east, counter-clockwise, with its unit: 30deg or 0.5236rad");
  if (input)
    cmd.add_option("--input-origin", args.input_origin,
                   "the input plan is in building coordinates (a DXF or Shapefile written with --origin): E,N,ROT\n"
                   "of its map frame, as for --origin; the plan is moved back into the map frame before writing");
}

Pose2 parseOrigin(const std::string& text, const std::string& field) {
  std::vector<std::string> parts;
  std::stringstream ss(text);
  for (std::string p; std::getline(ss, p, ',');) parts.push_back(p);
  const std::string usage = " (expected E,N,ROT with the rotation's unit, e.g. 500000,5400000,30deg)";
  if (parts.size() != 3) throw Error("'" + text + "': three comma-separated values" + usage, {}, 0, field);
  const auto number = [&](const std::string& s, std::string* rest) {
    const char* begin = s.c_str();
    while (std::isspace(static_cast<unsigned char>(*begin))) ++begin;
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin || !std::isfinite(v)) throw Error("'" + s + "' is not a number" + usage, {}, 0, field);
    std::string tail(end);
    while (!tail.empty() && std::isspace(static_cast<unsigned char>(tail.back()))) tail.pop_back();
    if (rest)
      *rest = tail;
    else if (!tail.empty())
      throw Error("'" + s + "' is not a number" + usage, {}, 0, field);
    return v;
  };
  const double e = number(parts[0], nullptr), n = number(parts[1], nullptr);
  std::string unit;
  const double rot = number(parts[2], &unit);
  for (char& c : unit) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  double theta = 0.0;
  if (unit == "deg" || unit == "\xc2\xb0")
    theta = deg2rad(rot);
  else if (unit == "rad")
    theta = rot;
  else if (unit.empty() && rot == 0.0)
    theta = 0.0;
  else if (unit.empty())
    throw Error("the rotation '" + parts[2] + "' needs its unit: " + parts[2] + "deg or " + parts[2] + "rad", {}, 0,
                field);
  else
    throw Error("unknown rotation unit '" + unit + "' (deg or rad)", {}, 0, field);
  return Pose2(e, n, theta);
}

std::optional<FloorplanGeoref> georefOf(const GeorefArgs& args) {
  if (args.crs.empty() && args.origin.empty()) return std::nullopt;
  if (args.crs.empty() != args.origin.empty())
    throw Error("--crs and --origin go together", {}, 0, args.crs.empty() ? "--crs" : "--origin");
  FloorplanGeoref g;
  g.crs = args.crs;
  g.origin = parseOrigin(args.origin, "--origin");
  return g;
}

void undoInputOrigin(const GeorefArgs& args, VectorMap& map, FloorplanExtras& extras, bool quiet) {
  if (args.input_origin.empty()) return;
  const Pose2 inv = parseOrigin(args.input_origin, "--input-origin").inverse();
  const auto back = [&](Vec2& p) { p = inv * p; };
  for (VectorMap* m : {&map, &extras.clutter})
    for (MapSegment& s : m->segments) {
      back(s.a);
      back(s.b);
      s.pane_angle = std::fmod(std::fmod(s.pane_angle + inv.theta, kPi) + kPi, kPi);
    }
  for (DoorOpening& d : extras.doors) back(d.a), back(d.b);
  for (RoomPolygon& r : extras.rooms)
    for (Vec2& p : r.ring) back(p);
  if (!quiet)
    std::cerr << "glassmap: input moved back into its map frame (--input-origin " << args.input_origin << ")\n";
}

std::string georefSummary(const FloorplanGeoref& g) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "in %s: map frame origin at E %.3f N %.3f, x axis %.6f deg from east", g.crs.c_str(),
                g.origin.x(), g.origin.y(), rad2deg(g.origin.theta));
  return buf;
}

}  // namespace glassmap::cli
