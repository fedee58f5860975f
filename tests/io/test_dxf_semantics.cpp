// CAD floorplans: layer names to materials (the AIA/NCS table and --layers rules) and what of a
// DXF is not geometry of the building (blocks, annotation, paper space, frozen and off layers).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"
#include "io_test_util.hpp"

namespace glassmap {
namespace {

using test::TempDir;

// tests/data/io/semantics.dxf (metres): walls on A-WALL (a line, a 2-segment polyline, a spline
// given by 3 fit points), a window block WIN1 inserted on A-GLAZ (2 lines on layer 0, a jamb on
// A-WALL, a hatch), dimensions (one through its *D1 block on A-ANNO-DIMS, one drawn by GDAL on
// A-WALL), a leader, a hatch and a text on A-WALL, a Defpoints line, a paper-space line, lines on
// a frozen (A-WALL-OLD) and an off (A-WALL-DEMO) layer, a door (A-DOOR arc and leaf), furniture
// (A-FURN) and one line on a layer no rule knows (MYSTERY).
const std::string kFixture = std::string(GLASSMAP_SOURCE_DIR) + "/tests/data/io/semantics.dxf";

bool hasSegment(const VectorMap& m, Vec2 a, Vec2 b, Material mat) {
  return std::any_of(m.segments.begin(), m.segments.end(), [&](const MapSegment& s) {
    const bool same =
        ((s.a - a).norm() < 1e-9 && (s.b - b).norm() < 1e-9) || ((s.a - b).norm() < 1e-9 && (s.b - a).norm() < 1e-9);
    return same && s.material == mat;
  });
}

const LayerReadCount* row(const FloorplanReadReport& r, const std::string& layer, const std::string& why) {
  for (const LayerReadCount& c : r.rows)
    if (c.layer == layer && c.why.find(why) != std::string::npos) return &c;
  return nullptr;
}

bool mentions(const std::vector<std::string>& lines, const std::string& what) {
  return std::any_of(lines.begin(), lines.end(),
                     [&](const std::string& l) { return l.find(what) != std::string::npos; });
}

TEST(DxfSemantics, ReadsOnlyTheBuilding) {
  FloorplanReadReport report;
  FloorplanReadOptions o;
  o.report = &report;
  const VectorMap m = readFloorplan(kFixture, o);
  EXPECT_EQ(m.count(Material::Wall), 7u);
  EXPECT_EQ(m.count(Material::Glass), 2u);
  EXPECT_EQ(m.segments.size(), 9u);
  // The window block on A-GLAZ: its layer-0 lines are glass, its A-WALL jamb stays wall.
  EXPECT_TRUE(hasSegment(m, {2, 0}, {3, 0}, Material::Glass));
  EXPECT_TRUE(hasSegment(m, {2, 0.05}, {3, 0.05}, Material::Glass));
  EXPECT_TRUE(hasSegment(m, {2, -0.1}, {2, 0.15}, Material::Wall));
  // The fit-point spline: a polyline through its fit points (GDAL 3.6 alone drops it).
  EXPECT_TRUE(hasSegment(m, {10, 8}, {11, 9}, Material::Wall));
  EXPECT_TRUE(hasSegment(m, {11, 9}, {12, 8}, Material::Wall));
  EXPECT_TRUE(hasSegment(m, {0, 8}, {0, 0}, Material::Wall));  // MYSTERY: unknown, read as wall
  for (const MapSegment& s : m.segments) {
    SCOPED_TRACE(std::to_string(s.a.x()) + "," + std::to_string(s.a.y()) + " " + std::to_string(s.b.x()) + "," +
                 std::to_string(s.b.y()));
    EXPECT_GE(std::min(s.a.y(), s.b.y()), -0.1);  // dimension lines at y = -1
    EXPECT_LE(std::max(s.a.y(), s.b.y()), 9.0);
    EXPECT_LE(std::max(s.a.x(), s.b.x()), 12.0);                                         // the hatch at 20..21
    EXPECT_FALSE(s.a.y() == s.b.y() && (s.a.y() == 1 || s.a.y() == 2 || s.a.y() == 4));  // frozen, off, furniture
    EXPECT_FALSE(s.a == Vec2(0, 0) && s.b == Vec2(3, 3));                                // paper space
    EXPECT_FALSE(s.a == Vec2(0, 0) && s.b == Vec2(0, 5));                                // Defpoints
    EXPECT_NE(s.a.x(), 8.0);                                                             // door leaf and swing
    EXPECT_GE(std::min(s.a.x(), s.b.x()) + std::min(s.a.y(), s.b.y()), -0.1);
    EXPECT_FALSE(s.a.x() > 5.9 && s.a.x() < 7.1 && s.a.y() > 5.9);  // leader
  }
  // The report says what was read as what, and why.
  EXPECT_TRUE(report.by_layer_names);
  const LayerReadCount* wall = row(report, "A-WALL", "*WALL*");
  ASSERT_NE(wall, nullptr);
  EXPECT_EQ(wall->outcome, "wall");
  EXPECT_EQ(wall->features, 4u);  // line, polyline, spline, the block's jamb
  EXPECT_EQ(wall->segments, 6u);
  const LayerReadCount* glass = row(report, "A-GLAZ", "*GLAZ*");
  ASSERT_NE(glass, nullptr);
  EXPECT_EQ(glass->outcome, "glass");
  EXPECT_EQ(glass->segments, 2u);
  for (const auto& [layer, why] : std::vector<std::pair<std::string, std::string>>{{"A-ANNO-DIMS", "dimension"},
                                                                                   {"A-WALL", "dimension"},
                                                                                   {"A-WALL", "leader"},
                                                                                   {"A-WALL", "hatch"},
                                                                                   {"A-GLAZ", "hatch"},
                                                                                   {"A-WALL", "text"},
                                                                                   {"A-WALL", "paper space"},
                                                                                   {"A-WALL-OLD", "frozen layer"},
                                                                                   {"A-WALL-DEMO", "layer off"},
                                                                                   {"Defpoints", "Defpoints"},
                                                                                   {"A-DOOR", "door"},
                                                                                   {"A-FURN", "furniture"}}) {
    const LayerReadCount* r = row(report, layer, why);
    ASSERT_NE(r, nullptr) << layer << " " << why;
    EXPECT_EQ(r->outcome, "ignored") << layer << " " << why;
    EXPECT_EQ(r->segments, 0u);
  }
  EXPECT_TRUE(mentions(report.warnings, "MYSTERY")) << formatReadReport(report);
  EXPECT_TRUE(mentions(report.notes, "1 spline(s) given only by fit points")) << formatReadReport(report);
  const std::string text = formatReadReport(report);
  EXPECT_NE(text.find("A-WALL-OLD"), std::string::npos) << text;
}

TEST(DxfSemantics, UserRulesComeFirst) {
  FloorplanReadReport report;
  FloorplanReadOptions o;
  o.report = &report;
  o.layer_rules = parseLayerRules("glass = mystery ; ignore=A-GLAZ,A-FURN");
  const VectorMap m = readFloorplan(kFixture, o);
  EXPECT_TRUE(hasSegment(m, {0, 8}, {0, 0}, Material::Glass));
  EXPECT_FALSE(hasSegment(m, {2, 0}, {3, 0}, Material::Glass));
  EXPECT_EQ(m.count(Material::Glass), 1u);
  EXPECT_EQ(m.count(Material::Wall), 6u);
  EXPECT_FALSE(mentions(report.warnings, "MYSTERY"));
  ASSERT_NE(row(report, "A-GLAZ", "--layers ignore=A-GLAZ"), nullptr);

  // Ignoring everything is an error, not an empty plan.
  o.layer_rules = parseLayerRules("ignore=*");
  EXPECT_THROW(readFloorplan(kFixture, o), Error);
  // Only glass: a warning.
  o.layer_rules = parseLayerRules("glass=A-WALL,MYSTERY");
  readFloorplan(kFixture, o);
  EXPECT_TRUE(mentions(report.warnings, "no line was read as wall"));
}

TEST(DxfSemantics, LayerTableAndRules) {
  auto role = [](const char* name) { return classifyLayer(name, {}).role; };
  EXPECT_EQ(role("A-WALL"), LayerRole::Wall);
  EXPECT_EQ(role("a-wall-extr"), LayerRole::Wall);
  EXPECT_EQ(role("S-COLS"), LayerRole::Wall);
  EXPECT_EQ(role("A-GLAZ"), LayerRole::Glass);
  EXPECT_EQ(role("A-GLAZ-SILL"), LayerRole::Glass);
  EXPECT_EQ(role("Fenster"), LayerRole::Glass);
  EXPECT_EQ(role("CURTAIN-WALL"), LayerRole::Glass);
  EXPECT_EQ(role("A-WALL-GLAZ"), LayerRole::Glass);
  EXPECT_EQ(role("XREF-BASE|A-GLAZ"), LayerRole::Glass);
  EXPECT_EQ(role("A-GLAZ-IDEN"), LayerRole::Ignore);  // window tags
  EXPECT_EQ(role("A-WALL-PATT"), LayerRole::Ignore);  // wall hatch
  EXPECT_EQ(role("A-DOOR"), LayerRole::Ignore);
  EXPECT_EQ(role("A-ANNO-DIMS"), LayerRole::Ignore);
  EXPECT_EQ(role("DEFPOINTS"), LayerRole::Ignore);
  EXPECT_EQ(role("A-FURN"), LayerRole::Ignore);
  EXPECT_EQ(role("A-GRID"), LayerRole::Ignore);
  const LayerDecision unknown = classifyLayer("0", {});
  EXPECT_EQ(unknown.role, LayerRole::Wall);
  EXPECT_FALSE(unknown.known);
  // OGR layer names (no CAD Layer field): only the glass names of the table apply.
  EXPECT_EQ(classifyLayer("doors", {}, false).role, LayerRole::Wall);
  EXPECT_EQ(classifyLayer("windows", {}, false).role, LayerRole::Glass);

  const auto rules = parseLayerRules("glass=A-GLAZ*,*WINDOW*;wall=A-WALL*;ignore=A-FURN*");
  ASSERT_EQ(rules.size(), 4u);
  EXPECT_EQ(rules[1].role, LayerRole::Glass);
  EXPECT_EQ(rules[1].pattern, "*WINDOW*");
  EXPECT_EQ(classifyLayer("A-DOOR", parseLayerRules("wall=*DOOR*")).role, LayerRole::Wall);
  EXPECT_TRUE(parseLayerRules("").empty());
  EXPECT_THROW(parseLayerRules("steel=X"), Error);
  EXPECT_THROW(parseLayerRules("glass="), Error);
  EXPECT_THROW(parseLayerRules("A-GLAZ"), Error);

  EXPECT_TRUE(globMatch("a-?all*", "A-WALL-EXTR"));
  EXPECT_TRUE(globMatch("*", ""));
  EXPECT_FALSE(globMatch("A-WALL", "A-WALL-EXTR"));
  EXPECT_FALSE(globMatch("*GLAZ", "A-GLAZ-X"));
}

TEST(DxfSemantics, OwnFilesNeedNoLayerNames) {
  TempDir dir;
  VectorMap m;
  MapSegment s;
  s.a = {0, 0};
  s.b = {1, 0};
  m.segments.push_back(s);
  s.material = Material::Glass;
  s.b = {0, 1};
  m.segments.push_back(s);
  for (const char* ext : {".dxf", ".geojson"}) {
    const auto path = dir / (std::string("own") + ext);
    writeFloorplan(path, m);
    FloorplanReadReport report;
    FloorplanReadOptions o;
    o.report = &report;
    const VectorMap back = readFloorplan(path, o);
    EXPECT_EQ(back.count(Material::Glass), 1u) << ext;
    EXPECT_FALSE(report.by_layer_names) << ext;  // material from the field or XDATA
    EXPECT_TRUE(report.warnings.empty()) << ext;
  }
}

}  // namespace
}  // namespace glassmap
