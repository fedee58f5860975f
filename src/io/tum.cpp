#include "glassmap/io/tum.hpp"

#include <cmath>
#include <fstream>
#include <string>

#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "text_parse.hpp"

namespace glassmap {

namespace fs = std::filesystem;

std::vector<StampedPose> readTum(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open for reading", path.string());
  const std::string name = path.string();
  io_detail::LineContext ctx{&name, 0};
  std::vector<StampedPose> poses;
  std::vector<std::string_view> tok;
  std::string line;
  static const char* const kFields[] = {"timestamp", "x", "y", "z", "qx", "qy", "qz", "qw"};
  while (std::getline(in, line)) {
    ++ctx.line;
    io_detail::splitBlanks(line, tok);
    if (tok.empty() || tok[0].front() == '#') continue;
    if (tok.size() != 8) ctx.fail("expected 8 values 'timestamp x y z qx qy qz qw', got " + std::to_string(tok.size()));
    double v[8];
    for (int i = 0; i < 8; ++i) {
      v[i] = ctx.number(tok[static_cast<std::size_t>(i)], kFields[i]);
      if (!std::isfinite(v[i])) ctx.fail("value is not finite", kFields[i]);
    }
    const double qx = v[4], qy = v[5], qz = v[6], qw = v[7];
    const double norm = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
    if (norm < 1e-9) ctx.fail("quaternion has zero length", "qw");
    StampedPose p;
    p.timestamp = v[0];
    // Yaw of a (possibly unnormalised) quaternion.
    p.pose = Pose2(v[1], v[2], std::atan2(2.0 * (qw * qz + qx * qy), qw * qw + qx * qx - qy * qy - qz * qz));
    poses.push_back(p);
  }
  if (in.bad()) throw Error("read error", name, ctx.line);
  return poses;
}

void writeTum(const fs::path& path, const std::vector<StampedPose>& poses) {
  writeAtomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp);
    if (!out) throw Error("cannot create", tmp.string());
    std::string line;
    out << "# timestamp x y z qx qy qz qw\n";
    for (const StampedPose& p : poses) {
      line.clear();
      const double half = 0.5 * p.pose.theta;
      const double values[] = {p.timestamp, p.pose.x(), p.pose.y(), 0.0, 0.0, 0.0, std::sin(half), std::cos(half)};
      for (std::size_t i = 0; i < 8; ++i) {
        if (i) line += ' ';
        io_detail::appendNumber(line, values[i]);
      }
      line += '\n';
      out << line;
    }
    out.flush();
    if (!out) throw Error("write failed (disk full?)", path.string());
  });
}

}  // namespace glassmap
