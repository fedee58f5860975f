// CAD layer names → materials: glob rules, the built-in table, the read report's text.
#include "glassmap/io/floorplan_layers.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "floorplan_detail.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap {

using io_detail::lower;

std::string_view toString(LayerRole role) {
  switch (role) {
    case LayerRole::Wall: return "wall";
    case LayerRole::Glass: return "glass";
    case LayerRole::Ignore: return "ignore";
  }
  return "?";
}

bool globMatch(std::string_view pattern, std::string_view name) {
  const std::string p = lower(pattern), s = lower(name);
  std::size_t i = 0, j = 0, star = std::string::npos, mark = 0;
  while (j < s.size()) {
    if (i < p.size() && (p[i] == '?' || p[i] == s[j])) {
      ++i, ++j;
    } else if (i < p.size() && p[i] == '*') {
      star = i++;
      mark = j;
    } else if (star != std::string::npos) {
      i = star + 1;
      j = ++mark;
    } else {
      return false;
    }
  }
  while (i < p.size() && p[i] == '*') ++i;
  return i == p.size();
}

// The built-in table. Names follow the AIA CAD Layer Guidelines / US National CAD Standard
// (discipline "A-", major group WALL, GLAZ, DOOR, FURN, ANNO, GRID, AREA, CLNG, EQPM; modifiers
// -IDEN tags, -PATT hatch patterns, -DIMS, -NOTE, -SYMB, -NPLT not plotted), the usual English
// and German words, and "Defpoints" (AutoCAD's layer of dimension definition points). ISO 13567
// names carry an element code (CI/SfB, Uniclass) whose opening classes mix doors and windows:
// such names match here by their descriptive suffix ("A-21-E-Walls") or need --layers.
// Order matters: annotation modifiers first (A-GLAZ-IDEN is a tag, not glass), then doors (an
// opening: the leaf is drawn open and the swing arc is no surface), glass before wall
// (A-WALL-GLAZ, CURTAIN-WALL are glass).
const std::vector<LayerRule>& standardLayerRules() {
  static const std::vector<LayerRule> table = [] {
    std::vector<LayerRule> t;
    auto add = [&](LayerRole role, std::string why, std::initializer_list<const char*> patterns) {
      for (const char* p : patterns) t.push_back({role, p, why});
    };
    add(LayerRole::Ignore, "dimension definition points", {"Defpoints"});
    add(LayerRole::Ignore, "annotation layer",
        {"*-IDEN*", "*-PATT*", "*-NOTE*", "*-SYMB*", "*-NPLT*", "*DIM*", "*BEMASS*", "*ANNO*", "*TEXT*", "*HATCH*",
         "*SCHRAFF*", "*TITLE*", "*TTLB*", "*VPORT*", "*VIEWPORT*", "*GRID*", "*AREA*"});
    add(LayerRole::Ignore, "door (an opening)", {"*DOOR*", "*TUER*"});
    add(LayerRole::Ignore, "furniture/equipment", {"*FURN*", "*MOEBEL*", "*EQPM*"});
    add(LayerRole::Ignore, "overhead (ceiling)", {"*CLNG*", "*CEIL*"});
    add(LayerRole::Glass, "", {"*GLAS*", "*GLAZ*", "*WINDOW*", "*FENSTER*", "*VITR*", "*CURTAIN*"});
    add(LayerRole::Wall, "", {"*WALL*", "*WAND*", "*MAUER*", "*COLS*", "*COLUMN*"});
    return t;
  }();
  return table;
}

std::vector<LayerRule> parseLayerRules(const std::string& text, const std::string& field) {
  std::vector<LayerRule> rules;
  std::stringstream all(text);
  std::string item;
  auto trim = [](std::string s) {
    const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
  };
  while (std::getline(all, item, ';')) {
    item = trim(item);
    if (item.empty()) continue;
    const auto eq = item.find('=');
    const std::string role = eq == std::string::npos ? std::string() : lower(trim(item.substr(0, eq)));
    LayerRule rule;
    if (role == "wall") {
      rule.role = LayerRole::Wall;
    } else if (role == "glass") {
      rule.role = LayerRole::Glass;
    } else if (role == "ignore") {
      rule.role = LayerRole::Ignore;
    } else {
      throw Error("expected ROLE=PATTERN[,PATTERN...] with ROLE wall, glass or ignore, got '" + item + "'", {}, 0,
                  field);
    }
    std::stringstream patterns(item.substr(eq + 1));
    std::string p;
    bool any = false;
    while (std::getline(patterns, p, ',')) {
      p = trim(p);
      if (p.empty()) continue;
      rule.pattern = p;
      rule.why = "--layers " + std::string(toString(rule.role)) + "=" + p;
      rules.push_back(rule);
      any = true;
    }
    if (!any) throw Error("no layer name pattern after '" + role + "='", {}, 0, field);
  }
  return rules;
}

LayerDecision classifyLayer(std::string_view name, const std::vector<LayerRule>& user, bool standard) {
  const auto bar = name.rfind('|');  // xref-dependent layer "XREF|A-WALL"
  const std::string_view base = bar == std::string_view::npos ? name : name.substr(bar + 1);
  for (const LayerRule& r : user)
    if (globMatch(r.pattern, name) || globMatch(r.pattern, base)) return {r.role, r.why, true};
  for (const LayerRule& r : standardLayerRules()) {
    if (!standard && r.role != LayerRole::Glass) continue;  // OGR layer names: only glass names
    if (globMatch(r.pattern, base)) {
      return {r.role, "standard " + r.pattern + (r.why.empty() ? "" : ": " + r.why), true};
    }
  }
  return {LayerRole::Wall, standard ? "unknown layer name" : "default", false};
}

std::string formatReadReport(const FloorplanReadReport& report) {
  std::size_t w_layer = 5, w_feat = 8, w_seg = 8;
  for (const LayerReadCount& r : report.rows) {
    w_layer = std::max(w_layer, r.layer.size());
    w_feat = std::max(w_feat, std::to_string(r.features).size());
    w_seg = std::max(w_seg, std::to_string(r.segments).size());
  }
  std::ostringstream out;
  auto row = [&](const std::string& layer, const std::string& feat, const std::string& seg, const std::string& what,
                 const std::string& why) {
    std::string line = "  " + layer + std::string(w_layer - layer.size() + 2, ' ');
    line += std::string(w_feat - feat.size(), ' ') + feat + "  " + std::string(w_seg - seg.size(), ' ') + seg;
    line += "  " + what + std::string(what.size() < 9 ? 9 - what.size() : 1, ' ') + why;
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out << line << "\n";
  };
  if (!report.rows.empty()) {
    out << "glassmap: floorplan layers read as:\n";
    row("layer", "features", "segments", "read as", "because");
    std::vector<LayerReadCount> rows = report.rows;  // grouped by layer, else in order of appearance
    std::stable_sort(rows.begin(), rows.end(),
                     [](const LayerReadCount& a, const LayerReadCount& b) { return lower(a.layer) < lower(b.layer); });
    for (const LayerReadCount& r : rows)
      row(r.layer, std::to_string(r.features), std::to_string(r.segments), r.outcome, r.why);
  }
  for (const std::string& n : report.notes) out << "glassmap: note: " << n << "\n";
  for (const std::string& w : report.warnings) out << "glassmap: warning: " << w << "\n";
  return out.str();
}

}  // namespace glassmap
