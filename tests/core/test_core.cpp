#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/core/pose2.hpp"

using namespace glassmap;
namespace fs = std::filesystem;

TEST(Angles, WrapStaysInHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(wrapAngle(kPi), kPi);
  EXPECT_DOUBLE_EQ(wrapAngle(-kPi), kPi);
  EXPECT_NEAR(wrapAngle(3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(wrapAngle(2 * kPi + 0.5), 0.5, 1e-12);
  EXPECT_NEAR(wrapAngle(-2 * kPi - 0.5), -0.5, 1e-12);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-100, 100);
  for (int i = 0; i < 1000; ++i) {
    const double a = u(rng);
    const double w = wrapAngle(a);
    EXPECT_GT(w, -kPi);
    EXPECT_LE(w, kPi);
    EXPECT_NEAR(std::sin(w), std::sin(a), 1e-9);
    EXPECT_NEAR(std::cos(w), std::cos(a), 1e-9);
  }
}

TEST(Angles, HalfTurnAndConversions) {
  EXPECT_NEAR(wrapHalfTurn(kPi + 0.25), 0.25, 1e-12);
  EXPECT_NEAR(wrapHalfTurn(-0.25), kPi - 0.25, 1e-12);
  EXPECT_DOUBLE_EQ(deg2rad(180.0), kPi);
  EXPECT_DOUBLE_EQ(rad2deg(kPi / 2), 90.0);
  EXPECT_NEAR(angleDiff(deg2rad(179), deg2rad(-179)), deg2rad(-2), 1e-12);
}

TEST(Pose2, ComposeInverseBetween) {
  const Pose2 a(1.0, 2.0, deg2rad(30));
  const Pose2 b(-0.5, 0.3, deg2rad(-100));
  EXPECT_TRUE(approxEqual(a * a.inverse(), Pose2()));
  EXPECT_TRUE(approxEqual(a.inverse() * a, Pose2()));
  EXPECT_TRUE(approxEqual(a * a.between(b), b));
  // Composition acts on points like applying one transform after the other.
  const Vec2 p(0.7, -1.1);
  EXPECT_TRUE(((a * b) * p).isApprox(a * (b * p), 1e-12));
  // A known case: a robot at (1,0) facing +y moving 1 m forward ends at (1,1).
  const Pose2 r(1, 0, kPi / 2);
  EXPECT_TRUE(approxEqual(r * Pose2(1, 0, 0), Pose2(1, 1, kPi / 2), 1e-12, 1e-12));
}

TEST(Pose2, InterpolationTakesTheShortWay) {
  const Pose2 a(0, 0, deg2rad(170));
  const Pose2 b(2, 4, deg2rad(-170));
  const Pose2 m = Pose2::interpolate(a, b, 0.5);
  EXPECT_NEAR(m.x(), 1.0, 1e-12);
  EXPECT_NEAR(m.y(), 2.0, 1e-12);
  EXPECT_NEAR(std::abs(m.theta), kPi, 1e-9);
  EXPECT_TRUE(approxEqual(Pose2::interpolate(a, b, 0.0), a));
  EXPECT_TRUE(approxEqual(Pose2::interpolate(a, b, 1.0), b, 1e-12, 1e-12));
}

TEST(Error, CarriesContextInMessage) {
  const Error e("expected a number", "log.clf", 12, "range[3]");
  EXPECT_EQ(std::string(e.what()), "log.clf:12: range[3]: expected a number");
  EXPECT_EQ(e.line(), 12u);
  EXPECT_EQ(e.file(), "log.clf");
  EXPECT_EQ(e.field(), "range[3]");
  EXPECT_EQ(std::string(Error("plain").what()), "plain");
}

TEST(AtomicFile, FailureLeavesOldFileAndNoTemporary) {
  const fs::path dir = fs::temp_directory_path() / "glassmap_atomic_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path target = dir / "out.txt";
  writeAtomically(target, [](const fs::path& tmp) { std::ofstream(tmp) << "old"; });
  EXPECT_THROW(writeAtomically(target,
                               [](const fs::path& tmp) {
                                 std::ofstream(tmp) << "partial";
                                 throw Error("boom");
                               }),
               Error);
  std::ifstream in(target);
  std::string content;
  in >> content;
  EXPECT_EQ(content, "old");
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
  fs::remove_all(dir);
}
