// What a run reports and the checks before localizing (pipeline/reports.hpp, localize_checks.hpp):
// shared by the command line and the Python module.
#include <gtest/gtest.h>

#include "glassmap/core/error.hpp"
#include "glassmap/pipeline/localize_checks.hpp"
#include "glassmap/pipeline/reports.hpp"

namespace glassmap::pipeline {
namespace {

TEST(Reports, ProfileJsonRoundTrip) {
  SensorProfile p;
  p.range_sigma_m = {0.013, 0.001, true};
  p.direct_sigma_deg = {3.5, 0.2, true};
  p.glass_offset_m = {0.004, 0.0, false};
  p.source = "calibrated from x.clf";
  p.wall_beams = 1234;
  p.glass_beams = 56;
  const nlohmann::json j = profileJson(p);
  EXPECT_EQ(j["fitted"], nlohmann::json({"range_sigma_m", "direct_sigma_deg"}));
  const SensorProfile q = profileFromJson(j);
  EXPECT_EQ(profileJson(q), j);
  EXPECT_TRUE(q.range_sigma_m.fitted);
  EXPECT_FALSE(q.glass_offset_m.fitted);
  EXPECT_DOUBLE_EQ(q.direct_sigma_deg.se, 0.2);
}

TEST(Reports, ProfileFromJsonRefusesUnknownKeysAndWrongTypes) {
  try {
    profileFromJson({{"range_sgima_m", 0.01}});
    FAIL() << "unknown key accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "range_sgima_m");
  }
  EXPECT_THROW(profileFromJson({{"w_hit", "high"}}), Error);
  EXPECT_THROW(profileFromJson({{"fitted", {"colour"}}}), Error);
  EXPECT_THROW(profileFromJson({{"wall_beams", -3}}), Error);
  // Keys the caller names are passed over (calibrate's report around a profile).
  EXPECT_DOUBLE_EQ(profileFromJson({{"log", "x.clf"}, {"w_hit", 0.7}}, {"log"}).w_hit.value, 0.7);
}

TEST(Reports, GridMemoryBudgetLeavesWhatTheLogDoesNotUse) {
  LaserLog log;
  log.scans.resize(10);
  for (LaserScan& s : log.scans) s.ranges.assign(100, 1.0f);
  EXPECT_EQ(gridMemoryBudget(log.memoryBytes() + 500, log), 500u);
  EXPECT_EQ(gridMemoryBudget(10, log), 1u);
}

TEST(LocalizeChecks, PlanAndInitialPose) {
  VectorMap map;
  EXPECT_THROW(checkLocalizationPlan(map, "plan.gpkg", "", false), Error);
  map.add({0, 0}, {20, 0}, Material::Wall);
  map.add({20, 0}, {20, 10}, Material::Glass);
  EXPECT_NO_THROW(checkLocalizationPlan(map, "plan.gpkg", "", false));
  EXPECT_THROW(checkLocalizationPlan(map, "plan.gpkg", "spans 2000 km", false), Error);
  EXPECT_NO_THROW(checkLocalizationPlan(map, "plan.gpkg", "spans 2000 km", true));  // units given: a warning only
  EXPECT_NO_THROW(checkInitialPose(map, Pose2(5, 5, 0), "plan.gpkg"));
  EXPECT_NO_THROW(checkInitialPose(map, Pose2(-1.0, 11.0, 0), "plan.gpkg"));  // within 0.5 m + 5% of the plan
  try {
    checkInitialPose(map, Pose2(500, 5, 0), "plan.gpkg");
    FAIL() << "a start 480 m off the plan was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "plan.gpkg");
    EXPECT_EQ(e.field(), "init");
    EXPECT_NE(e.message().find("outside the map's extent"), std::string::npos);
  }
}

TEST(Reports, CalibrationSourceNamesFiles) {
  EXPECT_EQ(calibrationSource("/data/run.clf", ""), "calibrated from run.clf against its own map");
  EXPECT_EQ(calibrationSource("run.clf", "plans/floor.dxf"), "calibrated from run.clf against floor.dxf");
}

}  // namespace
}  // namespace glassmap::pipeline
