// Sensor profiles on disk: round trip, refusal of implausible values, the calibration chart.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "glassmap/core/error.hpp"
#include "glassmap/io/sensor_profile.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "glassmap_test_sensor_profile";
  fs::create_directories(dir);
  return dir / name;
}

TEST(SensorProfileFile, RoundTripKeepsValuesErrorsAndWhatWasFitted) {
  SensorProfile p;
  p.range_sigma_m = {0.031, 0.0004, true};
  p.direct_sigma_deg = {4.2, 0.3, true};
  p.direct_peak = {0.55, 0.01, true};
  p.direct_floor = {0.05, 0.002, true};
  p.normal_lambda_per_deg = {0.012, 0.001, true};
  p.source = "calibrated from a test";
  const fs::path f = scratch("round.yaml");
  writeSensorProfile(f, p);
  const SensorProfile q = readSensorProfile(f);
  EXPECT_DOUBLE_EQ(q.range_sigma_m.value, 0.031);
  EXPECT_DOUBLE_EQ(q.range_sigma_m.se, 0.0004);
  EXPECT_TRUE(q.range_sigma_m.fitted);
  EXPECT_DOUBLE_EQ(q.direct_sigma_deg.value, 4.2);
  EXPECT_DOUBLE_EQ(q.direct_floor.value, 0.05);
  EXPECT_DOUBLE_EQ(q.normal_lambda_per_deg.value, 0.012);
  EXPECT_FALSE(q.w_hit.fitted);  // a prior stays a prior
  EXPECT_DOUBLE_EQ(q.w_hit.value, SensorProfile{}.w_hit.value);
  EXPECT_EQ(q.source, "calibrated from a test");
}

TEST(SensorProfileFile, HandWrittenSubsetKeepsDefaults) {
  const fs::path f = scratch("subset.yaml");
  std::ofstream(f) << "range_sigma_m: 0.05\ndirect_sigma_deg: 15\n";
  const SensorProfile q = readSensorProfile(f);
  EXPECT_DOUBLE_EQ(q.range_sigma_m.value, 0.05);
  EXPECT_DOUBLE_EQ(q.direct_sigma_deg.value, 15.0);
  EXPECT_DOUBLE_EQ(q.direct_peak.value, SensorProfile{}.direct_peak.value);
}

TEST(SensorProfileFile, ImplausibleValuesNameFileLineAndKey) {
  const fs::path f = scratch("bad.yaml");
  std::ofstream(f) << "range_sigma_m: 0.02\ndirect_peak: 1.7\n";
  try {
    readSensorProfile(f);
    FAIL() << "accepted a probability of 1.7";
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 2u);
    EXPECT_EQ(e.field(), "direct_peak");
    EXPECT_NE(std::string(e.what()).find("bad.yaml"), std::string::npos);
  }
  std::ofstream(f) << "range_sigma_m: -1\n";
  EXPECT_THROW(readSensorProfile(f), Error);
  std::ofstream(f) << "range_sigma_m: [1, 2]\n";
  EXPECT_THROW(readSensorProfile(f), Error);
  EXPECT_THROW(readSensorProfile(scratch("missing.yaml")), Error);
}

TEST(SensorProfileFile, ChartIsAPng) {
  SensorProfile p;
  std::vector<GlassAngleBin> bins(45);
  for (std::size_t b = 0; b < bins.size(); ++b) {
    bins[b].theta_lo = 2.0 * static_cast<double>(b);
    bins[b].theta_hi = bins[b].theta_lo + 2.0;
    bins[b].beams = 100;
    bins[b].direct = b < 2 ? 80 : 0;
    bins[b].mirror_beams = 50;
    bins[b].reflected = 5;
  }
  const fs::path f = scratch("chart.png");
  fs::remove(f);
  renderCalibrationChart(f, p, bins);
  std::ifstream in(f, std::ios::binary);
  char magic[4] = {};
  in.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  EXPECT_GT(fs::file_size(f), 5000u);
}

}  // namespace
}  // namespace glassmap
