#include "dxf_text.hpp"

#include <cpl_conv.h>

#include <cctype>
#include <charconv>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "floorplan_detail.hpp"
#include "glassmap/core/error.hpp"
#include "text_parse.hpp"

namespace glassmap::io_detail {

namespace fs = std::filesystem;

namespace {

/// One DXF group: code line and value line, both kept as written.
struct Group {
  std::string code, value;
  int number() const { return std::atoi(code.c_str()); }
  bool is(int c, std::string_view v) const { return number() == c && value == v; }
};

std::string trimCr(std::string s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == ' ')) s.pop_back();
  return s;
}

std::vector<Group> readGroups(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open DXF", path.string());
  std::vector<Group> groups;
  std::string code, value;
  while (std::getline(in, code)) {
    if (!std::getline(in, value)) {
      if (trimCr(code).empty()) break;
      throw Error("DXF ends inside a group", path.string());
    }
    groups.push_back({trimCr(code), trimCr(value)});
  }
  return groups;
}

void writeGroups(const fs::path& path, const std::vector<Group>& groups) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw Error("cannot write DXF", path.string());
  for (const Group& g : groups) out << g.code << '\n' << g.value << '\n';
  out.flush();
  if (!out) throw Error("write failed (disk full?)", path.string());
}

Group group(int code, std::string value) {
  std::string c = std::to_string(code);
  if (c.size() < 3) c.insert(0, 3 - c.size(), ' ');
  return {c, std::move(value)};
}

/// Sets the value of header variable `name` (the group after it), adding it before ENDSEC if absent.
void setHeaderVar(std::vector<Group>& g, const std::string& name, int code, const std::string& value) {
  for (std::size_t i = 0; i + 1 < g.size(); ++i) {
    if (g[i].is(9, name)) {
      g[i + 1].value = value;
      return;
    }
  }
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (g[i].is(0, "ENDSEC")) {
      g.insert(g.begin() + static_cast<std::ptrdiff_t>(i), {group(9, name), group(code, value)});
      return;
    }
  }
  throw Error("DXF header template has no HEADER section");
}

/// Inserts records at the end of table `table` and raises its entry count.
void addToTable(std::vector<Group>& g, const std::string& table, const std::vector<Group>& records, int n) {
  for (std::size_t i = 0; i + 1 < g.size(); ++i) {
    if (!(g[i].is(0, "TABLE") && g[i + 1].is(2, table))) continue;
    std::size_t j = i + 2;
    for (; j < g.size() && g[j].number() != 0; ++j) {
      if (g[j].number() == 70) g[j].value = std::to_string(std::atoi(g[j].value.c_str()) + n);
    }
    for (; j < g.size() && !g[j].is(0, "ENDTAB"); ++j) {
    }
    g.insert(g.begin() + static_cast<std::ptrdiff_t>(j), records.begin(), records.end());
    return;
  }
  throw Error("DXF header template has no " + table + " table");
}

std::string tableHandle(const std::vector<Group>& g, const std::string& table) {
  for (std::size_t i = 0; i + 2 < g.size(); ++i)
    if (g[i].is(0, "TABLE") && g[i + 1].is(2, table) && g[i + 2].number() == 5) return g[i + 2].value;
  return "0";
}

}  // namespace

void writeDxfHeaderTemplate(const fs::path& path) {
  const char* found = CPLFindFile("GDAL", "header.dxf");
  if (!found) throw Error("GDAL's DXF header template header.dxf not found (is GDAL_DATA set?)");
  std::vector<Group> g = readGroups(found);
  setHeaderVar(g, "$INSUNITS", 70, "     6");     // metres
  setHeaderVar(g, "$MEASUREMENT", 70, "     1");  // metric

  std::set<unsigned long> used;
  for (const Group& x : g)
    if (x.number() == 5 || x.number() == 105) used.insert(std::strtoul(x.value.c_str(), nullptr, 16));
  unsigned long next = 0x1000;
  auto handle = [&] {
    while (used.count(next)) ++next;
    used.insert(next);
    std::ostringstream s;
    s << std::uppercase << std::hex << next;
    return s.str();
  };
  const std::string layer_table = tableHandle(g, "LAYER");
  auto layer = [&](const std::string& name, int colour) {
    return std::vector<Group>{group(0, "LAYER"),
                              group(5, handle()),
                              group(330, layer_table),
                              group(100, "AcDbSymbolTableRecord"),
                              group(100, "AcDbLayerTableRecord"),
                              group(2, name),
                              group(70, "     0"),
                              group(62, "     " + std::to_string(colour)),
                              group(6, "Continuous"),
                              group(370, "    -3"),
                              group(390, "F")};
  };
  std::vector<Group> layers;
  // The building (WALL, GLASS), then the layers beside it (floorplan_extras.hpp).
  for (const auto& [name, colour] :
       {std::pair<const char*, int>{"WALL", 7}, {"GLASS", 4}, {"CLUTTER", 8}, {"DOOR", 3}, {"ROOMS", 5}}) {
    const std::vector<Group> l = layer(name, colour);
    layers.insert(layers.end(), l.begin(), l.end());
  }
  addToTable(g, "LAYER", layers, 5);
  const std::vector<Group> app{group(0, "APPID"),
                               group(5, handle()),
                               group(330, tableHandle(g, "APPID")),
                               group(100, "AcDbSymbolTableRecord"),
                               group(100, "AcDbRegAppTableRecord"),
                               group(2, "GLASSMAP"),
                               group(70, "     0")};
  addToTable(g, "APPID", app, 1);
  writeGroups(path, g);
}

void checkDxfGroupCodes(const fs::path& dxf) {
  std::ifstream in(dxf, std::ios::binary);
  if (!in) throw Error("cannot open", dxf.string());
  auto trim = [](std::string_view v) {
    while (!v.empty() && (v.back() == '\r' || v.back() == ' ' || v.back() == '\t')) v.remove_suffix(1);
    while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
    return v;
  };
  // GDAL 3.6's reader spins on a file whose last byte is a bare carriage return (found by
  // fuzzing: hang-final-cr.dxf); text DXF ends in a line feed or in "EOF" itself.
  in.seekg(0, std::ios::end);
  if (in.tellg() > 0) {
    in.seekg(-1, std::ios::end);
    if (in.get() == '\r') throw Error("DXF ends in a bare carriage return (damaged line endings)", dxf.string());
  }
  in.clear();
  in.seekg(0);
  std::string line;
  std::size_t number = 0, section_line = 0;
  long code = -1000;
  bool in_section = false, in_table = false, in_block = false, seen_eof = false;
  while (std::getline(in, line)) {
    ++number;
    // GDAL 3.6's binary DXF reader spins forever on damaged input (found by fuzzing:
    // tests/data/fuzz/fuzz_floorplan_dxf/hang-binary.dxf), and our files are text: refuse binary.
    if (number == 1 && line.starts_with("AutoCAD Binary DXF"))
      throw Error("binary DXF is not read: save the drawing as ASCII (text) DXF", dxf.string(), 1);
    // A NUL byte never belongs in a text DXF, and GDAL 3.6's DXF reader can spin forever on one
    // (found by fuzzing: tests/data/fuzz/fuzz_floorplan_dxf/hang-nul-byte.dxf).
    if (line.find('\0') != std::string::npos)
      throw Error("NUL byte in a text DXF (binary data or a damaged file)", dxf.string(), number);
    const std::string_view text = trim(line);
    if (number % 2 == 0) {  // a value line: only section structure is checked
      if (code != 0) continue;
      if (text == "SECTION") {
        if (in_section)
          throw Error("SECTION inside the section opened at line " + std::to_string(section_line) + " (missing ENDSEC)",
                      dxf.string(), number);
        in_section = true;
        section_line = number;
      } else if (text == "ENDSEC") {
        if (!in_section) throw Error("ENDSEC without SECTION", dxf.string(), number);
        if (in_table || in_block) throw Error("ENDSEC inside an open TABLE or BLOCK", dxf.string(), number);
        in_section = false;
      } else if (text == "TABLE" || text == "BLOCK") {  // the same pairing one level down
        bool& open = text == "TABLE" ? in_table : in_block;
        if (open || !in_section) throw Error(std::string(text) + " nested or outside a section", dxf.string(), number);
        open = true;
      } else if (text == "ENDTAB" || text == "ENDBLK") {
        bool& open = text == "ENDTAB" ? in_table : in_block;
        if (!open) throw Error(std::string(text) + " without its TABLE or BLOCK", dxf.string(), number);
        open = false;
      } else if (text == "EOF") {
        seen_eof = true;
        break;
      }
      continue;
    }
    if (text.empty() && in.peek() == std::char_traits<char>::eof()) break;  // trailing blank line
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), code);
    if (ec != std::errc() || ptr != text.data() + text.size() || code < -5 || code > 1071)
      throw Error("expected a DXF group code (an integer), got '" + std::string(text.substr(0, 40)) + "'", dxf.string(),
                  number);
  }
  if (in_section)
    throw Error("section opened at line " + std::to_string(section_line) + " is not closed by ENDSEC", dxf.string(),
                number);
  // GDAL's reader can spin at the end of a file that stops without the closing group, and on one
  // that goes on after it (found by fuzzing: hang-after-eof.dxf).
  if (!seen_eof) throw Error("truncated DXF: no '0 EOF' group at the end", dxf.string(), number);
  const std::size_t eof_line = number;
  while (std::getline(in, line)) {
    ++number;
    if (!trim(line).empty())
      throw Error("content after the closing '0 EOF' group of line " + std::to_string(eof_line), dxf.string(), number);
  }
}

double dxfUnitInMetres(const fs::path& dxf) {
  std::ifstream in(dxf, std::ios::binary);
  std::string code, value;
  bool want = false;
  while (std::getline(in, code) && std::getline(in, value)) {
    code = trimCr(code);
    value = trimCr(value);
    const int c = std::atoi(code.c_str());
    if (c == 0 && value == "ENDSEC") break;  // end of the HEADER section
    if (c == 9) {
      want = value == "$INSUNITS";
      continue;
    }
    if (!want) continue;
    switch (std::atoi(value.c_str())) {  // AutoCAD's $INSUNITS codes
      case 1: return 0.0254;             // inches
      case 2: return 0.3048;             // feet
      case 3: return 1609.344;           // miles
      case 4: return 0.001;              // millimetres
      case 5: return 0.01;               // centimetres
      case 6: return 1.0;                // metres
      case 7: return 1000.0;             // kilometres
      case 8: return 0.0254e-6;          // microinches
      case 9: return 0.0254e-3;          // mils
      case 10: return 0.9144;            // yards
      case 14: return 0.1;               // decimetres
      default: return 0.0;
    }
  }
  return 0.0;
}

void addDxfXData(const fs::path& dxf, const VectorMap& map, std::size_t extra_lines) {
  std::vector<Group> g = readGroups(dxf);
  std::vector<Group> out;
  out.reserve(g.size() + map.segments.size() * 7);
  bool in_entities = false;
  std::size_t entity = 0;
  bool in_line = false;
  auto flush = [&] {
    if (!in_line) return;
    if (entity >= map.segments.size() + extra_lines)
      throw Error("GDAL wrote more DXF entities than segments", dxf.string());
    if (entity >= map.segments.size()) {  // the extra layers' lines: no attributes to add
      ++entity;
      in_line = false;
      return;
    }
    const MapSegment& s = map.segments[entity++];
    auto kv = [](const char* key, auto v) {
      std::string text = std::string(key) + "=";
      appendNumber(text, v);
      return group(1000, text);
    };
    out.push_back(group(1001, "GLASSMAP"));
    out.push_back(group(1000, "material=" + std::string(toString(s.material))));
    out.push_back(kv("thickness", s.thickness));
    out.push_back(kv("pane_angle", s.pane_angle));
    out.push_back(kv("support", s.support));
    out.push_back(kv("evidence", s.evidence));
    in_line = false;
  };
  for (std::size_t i = 0; i < g.size(); ++i) {
    const Group& x = g[i];
    if (x.number() == 0) {
      flush();
      if (x.value == "ENDSEC")
        in_entities = false;
      else if (in_entities)
        in_line = x.value == "LWPOLYLINE" || x.value == "LINE";
    }
    if (x.is(2, "ENTITIES") && i > 0 && g[i - 1].is(0, "SECTION")) in_entities = true;
    out.push_back(x);
  }
  if (entity != map.segments.size() + extra_lines)
    throw Error("GDAL wrote " + std::to_string(entity) + " DXF line entities for " +
                    std::to_string(map.segments.size() + extra_lines) + " segments",
                dxf.string());
  writeGroups(dxf, out);
}

namespace {

/// An LWPOLYLINE through the fit points of a SPLINE entity given by fit points only (groups
/// [b, e) of the SPLINE); empty when the spline has control points (GDAL reads those itself).
std::vector<Group> fitSplineAsPolyline(const std::vector<Group>& g, std::size_t b, std::size_t e) {
  std::vector<Group> head, tail, points;
  bool control = false, closed = false;
  for (std::size_t i = b + 1; i < e; ++i) {
    const int c = g[i].number();
    if (c == 10) control = true;
    if (c == 70) closed = (std::atoi(g[i].value.c_str()) & 1) != 0;
    if (c == 11 || c == 21) points.push_back(group(c - 1, g[i].value));
    if (c == 5 || c == 6 || c == 8 || c == 48 || c == 60 || c == 62 || c == 67 || c == 330 || c == 370 || c == 420 ||
        c == 440)
      head.push_back(g[i]);
    if (c >= 1000) tail.push_back(g[i]);
  }
  if (control || points.size() < 4) return {};
  std::vector<Group> out{group(0, "LWPOLYLINE")};
  out.insert(out.end(), head.begin(), head.end());
  out.push_back(group(100, "AcDbEntity"));
  out.push_back(group(100, "AcDbPolyline"));
  out.push_back(group(90, std::to_string(points.size() / 2)));
  out.push_back(group(70, closed ? "1" : "0"));
  out.insert(out.end(), points.begin(), points.end());
  out.insert(out.end(), tail.begin(), tail.end());
  return out;
}

}  // namespace

DxfScan scanDxf(const fs::path& dxf) {
  const std::vector<Group> g = readGroups(dxf);
  DxfScan scan;
  std::vector<Group> patched;
  std::string section;
  bool in_layer_table = false;
  for (std::size_t i = 0; i < g.size();) {
    // One record: a code-0 group and the groups up to the next one.
    std::size_t e = i + 1;
    while (e < g.size() && g[e].number() != 0) ++e;
    const Group& x = g[i];
    if (x.number() == 0 && x.value == "SECTION" && i + 1 < e && g[i + 1].number() == 2) section = g[i + 1].value;
    if (x.number() == 0 && x.value == "ENDSEC") section.clear();
    if (x.number() == 0 && x.value == "TABLE") in_layer_table = i + 1 < e && g[i + 1].is(2, "LAYER");
    if (x.number() == 0 && x.value == "ENDTAB") in_layer_table = false;
    if (section == "TABLES" && in_layer_table && x.is(0, "LAYER")) {
      std::string name;
      DxfLayerState state;
      for (std::size_t k = i + 1; k < e; ++k) {
        if (g[k].number() == 2) name = g[k].value;
        if (g[k].number() == 70) state.frozen = (std::atoi(g[k].value.c_str()) & 1) != 0;
        if (g[k].number() == 62) state.off = std::atoi(g[k].value.c_str()) < 0;
      }
      scan.layers[lower(name)] = state;
    }
    if (section == "ENTITIES" && x.number() == 0) {
      for (std::size_t k = i + 1; k < e; ++k) {
        if (g[k].number() != 5) continue;
        std::string handle = g[k].value;
        for (char& c : handle) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        scan.entity_type[handle] = x.value;
        break;
      }
    }
    std::vector<Group> polyline;
    if ((section == "ENTITIES" || section == "BLOCKS") && x.is(0, "SPLINE")) polyline = fitSplineAsPolyline(g, i, e);
    if (!polyline.empty()) {
      ++scan.fit_splines;
      patched.insert(patched.end(), polyline.begin(), polyline.end());
    } else {
      patched.insert(patched.end(), g.begin() + static_cast<std::ptrdiff_t>(i),
                     g.begin() + static_cast<std::ptrdiff_t>(e));
    }
    i = e;
  }
  if (scan.fit_splines > 0) {
    for (const Group& x : patched) scan.patched += x.code + "\n" + x.value + "\n";
  }
  return scan;
}

std::string dxfIgnoreReason(const DxfScan& scan, bool paper_space, std::string_view handle, std::string_view subclasses,
                            std::string_view layer) {
  if (paper_space) return "paper space";
  std::string h(handle);
  for (char& c : h) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  const auto it = h.empty() ? scan.entity_type.end() : scan.entity_type.find(h);
  const std::string type = it == scan.entity_type.end() ? std::string() : it->second;
  static const std::pair<const char*, const char*> kinds[] = {
      {"DIMENSION", "dimension"}, {"LEADER", "leader"}, {"HATCH", "hatch"},    {"MPOLYGON", "hatch"},
      {"TEXT", "text"},           {"ATTRIB", "text"},   {"ATTDEF", "text"},    {"TOLERANCE", "tolerance"},
      {"VIEWPORT", "viewport"},   {"IMAGE", "image"},   {"WIPEOUT", "wipeout"}};
  for (const auto& [key, why] : kinds)
    if (type.find(key) != std::string::npos) return why;  // also ARC_DIMENSION, MULTILEADER, MTEXT
  static const std::pair<const char*, const char*> classes[] = {
      {"AcDbDimension", "dimension"}, {"AcDbLeader", "leader"},     {"AcDbMLeader", "leader"}, {"AcDbHatch", "hatch"},
      {"AcDbText", "text"},           {"AcDbMText", "text"},        {"AcDbAttribute", "text"}, {"AcDbFcf", "tolerance"},
      {"AcDbViewport", "viewport"},   {"AcDbRasterImage", "image"}, {"AcDbWipeout", "wipeout"}};
  for (const auto& [key, why] : classes)
    if (subclasses.find(key) != std::string_view::npos) return why;
  const auto state = scan.layers.find(lower(layer));
  if (state != scan.layers.end() && state->second.frozen) return "frozen layer";
  if (state != scan.layers.end() && state->second.off) return "layer off";
  return {};
}

}  // namespace glassmap::io_detail
