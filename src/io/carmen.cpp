#include "glassmap/io/carmen.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <string_view>
#include <vector>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/core/scan_spool.hpp"
#include "gzip_lines.hpp"
#include "text_parse.hpp"

namespace glassmap {

namespace fs = std::filesystem;
using io_detail::LineContext;

double carmenGuessFov(int num_beams) {
  switch (num_beams) {
    case 181:
    case 361: return kPi;
    case 180: return deg2rad(179.0);
    case 360: return deg2rad(179.5);
    case 401: return deg2rad(100.0);
    case 400: return deg2rad(99.75);
    default: return kPi;
  }
}

double carmenGuessAngleIncrement(int num_beams) {
  if (num_beams == 180 || num_beams == 181) return deg2rad(1.0);
  if (num_beams == 360 || num_beams == 361) return deg2rad(0.5);
  if (num_beams == 400 || num_beams == 401) return deg2rad(0.25);
  return num_beams > 1 ? carmenGuessFov(num_beams) / (num_beams - 1) : 0.0;
}

namespace {

constexpr double kCarmenDefaultMaxRange = 80.0;  // what CARMEN's readlog assumes for FLASER

/// Sequential reader over the numeric body of a line, naming fields in errors.
class Body {
 public:
  Body(std::span<const std::string_view> tokens, const LineContext& ctx, std::string_view type)
      : tokens_(tokens), ctx_(ctx), type_(type) {}

  std::size_t size() const { return tokens_.size(); }
  std::size_t remaining() const { return tokens_.size() - i_; }

  double num(const char* field) {
    need(1, field);
    return ctx_.number(tokens_[i_++], field);
  }
  /// A number that must be finite (poses, timestamps, the sensor configuration).
  double finite(const char* field) {
    const double v = num(field);
    if (!std::isfinite(v)) ctx_.fail(std::string(type_) + " line: value is not finite", field);
    return v;
  }
  long integer(const char* field) {
    need(1, field);
    return ctx_.integer(tokens_[i_++], field);
  }
  /// Reads `n` ranges; turns non-finite, negative and absurd (> kAbsurdRange) ones into kNoReturn.
  void ranges(long n, std::vector<float>& out, std::size_t& no_returns) {
    out.resize(static_cast<std::size_t>(n));
    std::string field;
    for (long k = 0; k < n; ++k) {
      double v = 0.0;
      if (!io_detail::tryParseDouble(tokens_[i_], v)) {
        field = "range[" + std::to_string(k) + "]";
        ctx_.number(tokens_[i_], field);  // throws with the field named
      }
      ++i_;
      if (!std::isfinite(v) || v < 0.0 || v > kAbsurdRange) {
        out[static_cast<std::size_t>(k)] = kNoReturn;
        ++no_returns;
      } else {
        out[static_cast<std::size_t>(k)] = static_cast<float>(v);
      }
    }
  }
  void skip(long n) { i_ += static_cast<std::size_t>(n); }

  /// Checks that exactly `expected` tokens remain; `what` describes them.
  void expectRemaining(std::size_t expected, const std::string& what, const char* field) const {
    if (remaining() != expected)
      ctx_.fail(std::string(type_) + " line needs " + what + " (" + std::to_string(expected) +
                    " values) here but has " + std::to_string(remaining()) + " (truncated line or wrong count?)",
                field);
  }
  void expectAtLeast(std::size_t expected, const std::string& what, const char* field) const {
    if (remaining() < expected)
      ctx_.fail(std::string(type_) + " line ends early: needs " + what + " (" + std::to_string(expected) +
                    " values) but has " + std::to_string(remaining()) + " (truncated line?)",
                field);
  }

 private:
  void need(std::size_t n, const char* field) const {
    if (remaining() < n) ctx_.fail(std::string(type_) + " line ends before this field (truncated line?)", field);
  }

  std::span<const std::string_view> tokens_;
  const LineContext& ctx_;
  std::string_view type_;
  std::size_t i_ = 0;
};

/// The numeric body of a line: tokens after the type up to the host name. CARMEN lines end in
/// "timestamp hostname logger_timestamp"; the host (the only word) and what follows are dropped.
std::span<const std::string_view> numericBody(const std::vector<std::string_view>& tok) {
  std::size_t end = tok.size();
  if (end >= 3 && !io_detail::isNumber(tok[end - 2]) && io_detail::isNumber(tok[end - 1])) {
    end -= 2;  // timestamp host logger_timestamp
  } else if (end >= 2 && !io_detail::isNumber(tok[end - 1])) {
    end -= 1;  // timestamp host
  }
  return std::span<const std::string_view>(tok).subspan(1, end - 1);
}

long checkedCount(long n, const LineContext& ctx, const char* field) {
  if (n < 0 || n > 1'000'000) ctx.fail("implausible count " + std::to_string(n), field);
  return n;
}

class CarmenParser {
 public:
  CarmenParser(const fs::path& path, const CarmenCallbacks& cb, const CarmenReadOptions& opt)
      : reader_(path), cb_(cb), opt_(opt) {
    ctx_.file = &reader_.name();
  }

  LogReadStats run() {
    std::string_view line;
    while (reader_.next(line)) {
      ++stats_.lines;
      if (opt_.progress && (stats_.lines & 4095) == 0) opt_.progress(reader_.fileOffset(), reader_.fileBytes());
      ctx_.line = reader_.lineNumber();
      io_detail::splitBlanks(line, tokens_);
      if (tokens_.empty() || tokens_[0].front() == '#') {
        ++stats_.comment_lines;
        continue;
      }
      dispatch();
    }
    if (opt_.progress) opt_.progress(reader_.fileBytes(), reader_.fileBytes());
    return stats_;
  }

 private:
  void dispatch() {
    const std::string_view type = tokens_[0];
    if (type == "FLASER" || type == "RLASER") {
      oldLaser(type == "FLASER" ? 1 : 2);
    } else if (type.starts_with("ROBOTLASER") && type.size() == 11 && type[10] >= '1' && type[10] <= '9') {
      robotLaser(type[10] - '0');
    } else if (type.starts_with("RAWLASER") && type.size() == 9 && type[8] >= '1' && type[8] <= '9') {
      rawLaser(type[8] - '0');
    } else if (type == "ODOM") {
      odom();
    } else if (type == "TRUEPOS") {
      truePos();
    } else if (type == "PARAM") {
      param();
    } else {
      ++stats_.skipped_lines;
      ++stats_.skipped_by_type[std::string(type)];
    }
  }

  Pose2 pose(Body& b, const char* fx, const char* fy, const char* ft) {
    const double x = b.finite(fx), y = b.finite(fy), t = b.finite(ft);
    return Pose2(x, y, t);
  }

  void emit(LaserScan&& scan) {
    if (opt_.laser_id != 0 && scan.laser_id != opt_.laser_id) {
      ++stats_.filtered_scans;
      return;
    }
    ++stats_.scans;
    if (have_scan_time_) {  // counted, not fatal: mapping uses the poses, not the clock
      if (scan.timestamp < last_scan_time_) ++stats_.backward_timestamps;
      if (scan.timestamp == last_scan_time_) ++stats_.repeated_timestamps;
    }
    have_scan_time_ = true;
    last_scan_time_ = scan.timestamp;
    if (cb_.on_scan) cb_.on_scan(std::move(scan));
  }

  // FLASER/RLASER num_readings r... x y theta odom_x odom_y odom_theta timestamp [host logger_ts]
  void oldLaser(int id) {
    Body b(numericBody(tokens_), ctx_, tokens_[0]);
    LaserScan s;
    s.laser_id = id;
    const long n = checkedCount(b.integer("num_readings"), ctx_, "num_readings");
    b.expectRemaining(static_cast<std::size_t>(n) + 7, std::to_string(n) + " ranges, 6 pose values and a timestamp",
                      "num_readings");
    b.ranges(n, s.ranges, stats_.no_return_ranges);
    s.laser_pose = pose(b, "x", "y", "theta");
    s.odom_pose = pose(b, "odom_x", "odom_y", "odom_theta");
    s.has_odom = true;
    s.timestamp = b.finite("timestamp");
    s.start_angle = -0.5 * kPi;  // CARMEN's readlog assumes a SICK centred on the heading
    s.angular_step = carmenGuessAngleIncrement(static_cast<int>(n));
    s.max_range = opt_.flaser_max_range > 0.0 ? opt_.flaser_max_range : (id == 1 ? front_max_range_ : rear_max_range_);
    emit(std::move(s));
  }

  // Sensor configuration: laser_type start_angle fov angular_res max_range accuracy remission_mode
  void laserConfig(Body& b, LaserScan& s) {
    b.integer("laser_type");
    s.start_angle = b.finite("start_angle");
    const double fov = b.finite("fov");
    s.angular_step = b.finite("angular_resolution");
    s.max_range = b.finite("maximum_range");
    b.num("accuracy");
    b.integer("remission_mode");
    fov_ = fov;
  }

  void fillStepFromFov(LaserScan& s, long n) const {
    if (s.angular_step == 0.0 && n > 1) s.angular_step = fov_ / static_cast<double>(n - 1);
  }

  // ROBOTLASERn config n r... [m rem...] laser_x laser_y laser_theta robot_x robot_y robot_theta
  //   tv rv forward_safety_dist side_safety_dist turn_axis timestamp [host logger_ts]
  void robotLaser(int id) {
    Body b(numericBody(tokens_), ctx_, tokens_[0]);
    LaserScan s;
    s.laser_id = id;
    laserConfig(b, s);
    const long n = checkedCount(b.integer("num_readings"), ctx_, "num_readings");
    constexpr std::size_t kTail = 12;  // 6 pose values, 5 motion values, timestamp
    b.expectAtLeast(static_cast<std::size_t>(n) + kTail,
                    std::to_string(n) + " ranges, 11 pose/motion values and a timestamp", "num_readings");
    b.ranges(n, s.ranges, stats_.no_return_ranges);
    if (b.remaining() != kTail) {  // the newer form carries num_remissions and remissions
      const long m = checkedCount(b.integer("num_remissions"), ctx_, "num_remissions");
      b.expectRemaining(static_cast<std::size_t>(m) + kTail,
                        std::to_string(m) + " remissions, 11 pose/motion values and a timestamp", "num_remissions");
      b.skip(m);
    }
    s.laser_pose = pose(b, "laser_x", "laser_y", "laser_theta");
    s.odom_pose = pose(b, "robot_x", "robot_y", "robot_theta");
    s.has_odom = true;
    b.num("tv");
    b.num("rv");
    b.num("forward_safety_dist");
    b.num("side_safety_dist");
    b.num("turn_axis");
    s.timestamp = b.finite("timestamp");
    fillStepFromFov(s, n);
    emit(std::move(s));
  }

  // RAWLASERn config n r... m rem... timestamp [host logger_ts]
  void rawLaser(int id) {
    Body b(numericBody(tokens_), ctx_, tokens_[0]);
    LaserScan s;
    s.laser_id = id;
    s.has_laser_pose = false;
    laserConfig(b, s);
    const long n = checkedCount(b.integer("num_readings"), ctx_, "num_readings");
    b.expectAtLeast(static_cast<std::size_t>(n) + 2, std::to_string(n) + " ranges, num_remissions and a timestamp",
                    "num_readings");
    b.ranges(n, s.ranges, stats_.no_return_ranges);
    const long m = checkedCount(b.integer("num_remissions"), ctx_, "num_remissions");
    b.expectRemaining(static_cast<std::size_t>(m) + 1, std::to_string(m) + " remissions and a timestamp",
                      "num_remissions");
    b.skip(m);
    s.timestamp = b.finite("timestamp");
    fillStepFromFov(s, n);
    emit(std::move(s));
  }

  // ODOM x y theta tv rv accel timestamp [host logger_ts]
  void odom() {
    Body b(numericBody(tokens_), ctx_, tokens_[0]);
    b.expectRemaining(7, "x y theta tv rv accel timestamp", "x");
    StampedPose p;
    p.pose = pose(b, "x", "y", "theta");
    p.tv = b.finite("tv");
    p.rv = b.finite("rv");
    b.num("accel");
    p.timestamp = b.finite("timestamp");
    ++stats_.odometry;
    if (cb_.on_odometry) cb_.on_odometry(p);
  }

  // TRUEPOS true_x true_y true_theta odom_x odom_y odom_theta timestamp [host logger_ts]
  void truePos() {
    Body b(numericBody(tokens_), ctx_, tokens_[0]);
    b.expectRemaining(7, "true_x true_y true_theta odom_x odom_y odom_theta timestamp", "true_x");
    StampedPose p;
    p.pose = pose(b, "true_x", "true_y", "true_theta");
    pose(b, "odom_x", "odom_y", "odom_theta");
    p.timestamp = b.finite("timestamp");
    ++stats_.true_poses;
    if (cb_.on_true_pose) cb_.on_true_pose(p);
  }

  // PARAM name value [timestamp host logger_ts]
  void param() {
    if (tokens_.size() < 3) ctx_.fail("PARAM line needs a name and a value", "value");
    const std::string name(tokens_[1]), value(tokens_[2]);
    if (name == "robot_front_laser_max" || name == "robot_rear_laser_max") {
      const double v = ctx_.number(tokens_[2], name);
      if (v > 0.0) (name == "robot_front_laser_max" ? front_max_range_ : rear_max_range_) = v;
    }
    ++stats_.params;
    if (cb_.on_param) cb_.on_param(name, value);
  }

  io_detail::GzipLineReader reader_;
  const CarmenCallbacks& cb_;
  CarmenReadOptions opt_;
  LineContext ctx_;
  LogReadStats stats_;
  std::vector<std::string_view> tokens_;
  double front_max_range_ = kCarmenDefaultMaxRange, rear_max_range_ = kCarmenDefaultMaxRange;
  double fov_ = 0.0;
  bool have_scan_time_ = false;
  double last_scan_time_ = 0.0;
};

// ---------------------------------------------------------------------------------------------
// Writing

/// Appends " v0 v1 ...".
void appendNumbers(std::string& out, std::initializer_list<double> values) {
  for (double v : values) {
    out += ' ';
    io_detail::appendNumber(out, v);
  }
}

void appendPose(std::string& out, const Pose2& p) { appendNumbers(out, {p.x(), p.y(), p.theta}); }

void appendTail(std::string& out, double timestamp) {
  appendNumbers(out, {timestamp});
  out += " glassmap ";
  io_detail::appendNumber(out, timestamp);
  out += '\n';
}

void appendScan(std::string& out, const LaserScan& s) {
  if (s.laser_id < 1 || s.laser_id > 9) throw Error("laser_id must be 1..9, got " + std::to_string(s.laser_id));
  out += "ROBOTLASER";
  out += static_cast<char>('0' + s.laser_id);
  out += " 0";  // laser_type: SICK LMS
  appendNumbers(out, {s.start_angle, s.fieldOfView(), s.angular_step, s.max_range});
  out += " 0.01 0 ";  // accuracy, remission_mode
  io_detail::appendNumber(out, s.ranges.size());
  for (float r : s.ranges) {
    out += ' ';
    io_detail::appendNumber(out, r);
  }
  out += " 0";  // num_remissions
  appendPose(out, s.laser_pose);
  appendPose(out, s.has_odom ? s.odom_pose : s.laser_pose);
  out += " 0 0 0 0 0";  // tv rv forward_safety_dist side_safety_dist turn_axis
  appendTail(out, s.timestamp);
}

}  // namespace

LogReadStats forEachCarmenRecord(const fs::path& path, const CarmenCallbacks& callbacks,
                                 const CarmenReadOptions& options) {
  CarmenParser parser(path, callbacks, options);
  return parser.run();
}

LaserLog readCarmenLog(const fs::path& path, const CarmenReadOptions& options) {
  LaserLog log;
  CarmenCallbacks cb;
  std::size_t bytes = 0;  // the log in memory, counted as it grows
  std::shared_ptr<ScanSpool> spool;
  MaxRangeCodeFinder codes;
  cb.on_scan = [&](LaserScan&& s) {
    if (options.detect_max_range_code)
      for (std::size_t i = 0; i < s.ranges.size(); ++i) codes.add(s.laser_id, s.ranges[i], i);
    if (spool) return spool->append(s);
    bytes += s.memoryBytes();
    if (!options.spool_directory.empty() && bytes > options.spool_above_bytes) {
      // Too large for memory: the scans so far and every later one go to disk.
      spool = std::make_shared<ScanSpool>(options.spool_directory);
      for (const LaserScan& kept : log.scans) spool->append(kept);
      spool->append(s);
      std::vector<LaserScan>().swap(log.scans);
      return;
    }
    if (options.max_memory_bytes > 0 && bytes > options.max_memory_bytes)
      throw Error("the log needs more than " + std::to_string(options.max_memory_bytes / 1000000) +
                      " MB in memory after " + std::to_string(log.scans.size()) + " scans (the memory limit)",
                  path.string());
    log.scans.push_back(std::move(s));
  };
  cb.on_odometry = [&](const StampedPose& p) { log.odometry.push_back(p); };
  cb.on_true_pose = [&](const StampedPose& p) { log.true_poses.push_back(p); };
  cb.on_param = [&](const std::string& k, const std::string& v) { log.params[k] = v; };
  log.stats = forEachCarmenRecord(path, cb, options);
  if (spool) {
    spool->flush();
    log.spooled = SpooledScans{spool, Vec2::Zero(), {}, spoolBlockBytes(options.spool_above_bytes)};
  }
  if (options.detect_max_range_code) applyMaxRangeCodes(log, codes);
  if (options.require_scans && log.scanCount() == 0) {
    std::string what = log.stats.lines == 0 ? "file is empty" : std::to_string(log.stats.lines) + " lines read";
    throw Error("no laser scans (ROBOTLASER1, FLASER, RLASER or RAWLASER1..4 lines) in log (" + what + ")",
                path.string());
  }
  return log;
}

void writeCarmenLog(const fs::path& path, const LaserLog& log) {
  const auto isWord = [](const std::string& w) { return !w.empty() && w.find_first_of(" \t\n") == w.npos; };
  for (const auto& [name, value] : log.params) {
    if (!isWord(name) || !isWord(value))
      throw Error("PARAM name and value must be single non-empty words: '" + name + "' = '" + value + "'",
                  path.string());
  }
  // The temporary keeps the target's extension, so a ".gz" target is written compressed.
  writeAtomically(path, [&](const fs::path& tmp) {
    io_detail::GzipLineWriter w(tmp);
    std::string out;
    out.reserve(1 << 16);
    out += "# written by glassmap\n";
    out += "# message formats defined: PARAM ROBOTLASER1 ODOM TRUEPOS\n";
    out +=
        "# ROBOTLASER1 laser_type start_angle field_of_view angular_resolution maximum_range accuracy "
        "remission_mode num_readings [range_readings] num_remissions laser_pose_x laser_pose_y "
        "laser_pose_theta robot_pose_x robot_pose_y robot_pose_theta laser_tv laser_rv "
        "forward_safety_dist side_safty_dist turn_axis timestamp hostname logger_timestamp\n";
    for (const auto& [name, value] : log.params) {
      out += "PARAM " + name + ' ' + value + " 0 glassmap 0\n";
    }
    // Merge the three time-ordered streams; on equal times odometry first, as CARMEN's logger does.
    std::size_t i = 0, j = 0, k = 0;
    const auto& scans = log.scans;
    const auto& odo = log.odometry;
    const auto& tru = log.true_poses;
    constexpr double kEnd = std::numeric_limits<double>::infinity();
    while (i < scans.size() || j < odo.size() || k < tru.size()) {
      const double ts = i < scans.size() ? scans[i].timestamp : kEnd;
      const double to = j < odo.size() ? odo[j].timestamp : kEnd;
      const double tt = k < tru.size() ? tru[k].timestamp : kEnd;
      if (j < odo.size() && to <= ts && to <= tt) {
        const StampedPose& p = odo[j++];
        out += "ODOM";
        appendPose(out, p.pose);
        appendNumbers(out, {p.tv, p.rv});
        out += " 0";
        appendTail(out, p.timestamp);
      } else if (k < tru.size() && tt <= ts) {
        const StampedPose& p = tru[k++];
        out += "TRUEPOS";
        appendPose(out, p.pose);
        appendPose(out, p.pose);
        appendTail(out, p.timestamp);
      } else {
        appendScan(out, scans[i++]);
      }
      if (out.size() > (1 << 15)) {
        w.write(out);
        out.clear();
      }
    }
    w.write(out);
    w.close();
  });
}

}  // namespace glassmap
