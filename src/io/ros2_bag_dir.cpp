// rosbag2 directories: metadata.yaml (rosbag2_bagfile_information) and the files it lists, with
// rosbag2's FILE (whole files zstd-compressed) and MESSAGE (each message zstd-compressed) modes.

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <map>

#include <yaml-cpp/yaml.h>

#include "glassmap/core/error.hpp"
#include "mcap_compress.hpp"
#include "ros2_bag_detail.hpp"

namespace glassmap::ros2 {
namespace {

namespace fs = std::filesystem;

/// Decompressed copies of FILE-mode files, removed with the reader (also when opening fails).
struct Temporaries {
  std::vector<fs::path> paths;
  Temporaries() = default;
  Temporaries(const Temporaries&) = delete;
  Temporaries& operator=(const Temporaries&) = delete;
  ~Temporaries() {
    std::error_code ec;
    for (const auto& t : paths) fs::remove(t, ec);
  }
};

class DirectoryReader final : public BagReader {
 public:
  explicit DirectoryReader(const fs::path& dir);
  const std::vector<BagTopic>& topics() const override { return topics_; }
  void forEach(const std::set<std::string>& topic_names, const std::function<bool(const BagMessage&)>& fn,
               const std::function<void(std::uint64_t, std::uint64_t)>& progress = {}) const override;
  BagStorage storage() const override { return storage_; }
  std::vector<fs::path> files() const override { return files_; }
  std::vector<std::string> notes() const override { return notes_; }

 private:
  Temporaries temporaries_;  // first: destroyed after the readers
  std::vector<std::unique_ptr<BagReader>> readers_;
  std::vector<fs::path> files_;
  std::vector<std::uint64_t> sizes_;
  std::vector<BagTopic> topics_;
  std::vector<std::map<const BagTopic*, const BagTopic*>> remap_;  ///< per file: its topic → merged topic
  BagStorage storage_ = BagStorage::Sqlite3;
  bool message_compression_ = false;
  std::vector<std::string> notes_;
};

std::string scalar(const YAML::Node& node, const char* key, const std::string& file) {
  const YAML::Node v = node[key];
  if (!v) return "";
  if (!v.IsScalar()) throw Error(std::string("'") + key + "' is not a scalar", file, v.Mark().line + 1, key);
  return v.as<std::string>();
}

fs::path temporaryFor(const fs::path& compressed) {
  static std::atomic<int> counter{0};
  return fs::temp_directory_path() / ("glassmap-bag-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) +
                                      "-" + compressed.stem().string());
}

DirectoryReader::DirectoryReader(const fs::path& dir) {
  const fs::path meta = dir / "metadata.yaml";
  const std::string mname = meta.string();
  YAML::Node info;
  try {
    info = YAML::LoadFile(meta.string())["rosbag2_bagfile_information"];
  } catch (const YAML::BadFile&) {
    throw Error("cannot read the bag's metadata.yaml", mname);
  } catch (const YAML::Exception& e) {
    throw Error(e.msg, mname, static_cast<std::size_t>(e.mark.line + 1));
  }
  if (!info || !info.IsMap()) throw Error("no rosbag2_bagfile_information map", mname);
  const std::string storage = scalar(info, "storage_identifier", mname);
  const std::string format = scalar(info, "compression_format", mname);
  const std::string mode = scalar(info, "compression_mode", mname);
  if (storage == "mcap")
    storage_ = BagStorage::Mcap;
  else if (storage != "sqlite3" && !storage.empty())
    throw Error("unknown storage_identifier '" + storage + "' (sqlite3 or mcap)", mname, 0, "storage_identifier");
  if (!format.empty() && format != "zstd")
    throw Error("unknown compression_format '" + format + "' (zstd)", mname, 0, "compression_format");
  const bool file_mode = !format.empty() && (mode == "FILE" || mode == "file");
  message_compression_ = !format.empty() && (mode == "MESSAGE" || mode == "message");
  if (!format.empty() && !file_mode && !message_compression_)
    throw Error("unknown compression_mode '" + mode + "' (FILE or MESSAGE)", mname, 0, "compression_mode");
  if (!format.empty()) notes_.push_back("rosbag2 " + format + " compression, mode " + mode);

  const YAML::Node paths = info["relative_file_paths"];
  if (!paths || !paths.IsSequence()) throw Error("no relative_file_paths list", mname, 0, "relative_file_paths");
  for (const auto& p : paths) {
    if (!p.IsScalar()) throw Error("an entry is not a path", mname, p.Mark().line + 1, "relative_file_paths");
    const fs::path rel = p.as<std::string>();
    fs::path file = dir / rel;
    std::error_code ec;
    // Older rosbag2 versions wrote the paths with the bag folder's name in front.
    if (!fs::exists(file, ec) && fs::exists(dir / rel.filename(), ec)) file = dir / rel.filename();
    // FILE mode lists the names before or after compression, depending on the rosbag2 version.
    if (file_mode && !fs::exists(file, ec) && fs::exists(file.string() + ".zstd", ec)) file += ".zstd";
    if (!fs::is_regular_file(file, ec))
      throw Error("lists '" + rel.string() + "', which is not in the bag folder", mname, p.Mark().line + 1,
                  "relative_file_paths");
    files_.push_back(file);
    sizes_.push_back(fs::file_size(file, ec));
    fs::path readable = file;
    if (file_mode || file.extension() == ".zstd") {
      readable = temporaryFor(file);
      temporaries_.paths.push_back(readable);
      zstdDecompressFile(file, readable);
    }
    try {
      readers_.push_back(openBagFile(readable));
    } catch (const Error& e) {
      if (readable == file) throw;
      throw Error(e.message() + " (after zstd decompression)", file.string(), e.line(), e.field());
    }
  }
  if (!readers_.empty()) storage_ = readers_.front()->storage();

  // Topics merged by name, in order of first appearance.
  for (const auto& r : readers_) {
    for (const BagTopic& t : r->topics()) {
      auto it = std::find_if(topics_.begin(), topics_.end(), [&](const BagTopic& o) { return o.name == t.name; });
      if (it == topics_.end()) {
        topics_.push_back(t);
        topics_.back().message_count = 0;
        it = topics_.end() - 1;
      }
      it->message_count += t.message_count;
    }
    for (const auto& n : r->notes()) notes_.push_back(n);
  }
  for (const auto& r : readers_) {
    auto& m = remap_.emplace_back();
    for (const BagTopic& t : r->topics())
      m[&t] = &*std::find_if(topics_.begin(), topics_.end(), [&](const BagTopic& o) { return o.name == t.name; });
  }
}

void DirectoryReader::forEach(const std::set<std::string>& topic_names,
                              const std::function<bool(const BagMessage&)>& fn,
                              const std::function<void(std::uint64_t, std::uint64_t)>& progress) const {
  std::uint64_t total = 0, before = 0;
  for (auto s : sizes_) total += s;
  std::vector<std::uint8_t> plain;
  for (std::size_t i = 0; i < readers_.size(); ++i) {
    bool stopped = false;
    const std::string name = files_[i].string();
    std::uint64_t index = 0;
    std::function<void(std::uint64_t, std::uint64_t)> sub;
    if (progress)
      sub = [&](std::uint64_t done, std::uint64_t all) {
        progress(before + (all ? sizes_[i] * std::min(done, all) / all : 0), total);
      };
    readers_[i]->forEach(
        topic_names,
        [&](const BagMessage& m) {
          BagMessage out = m;
          out.topic = remap_[i].at(m.topic);
          ++index;
          if (message_compression_) {
            zstdDecompressAny(m.data, plain, name, "message " + std::to_string(index) + " on " + m.topic->name);
            out.data = plain;
          }
          stopped = !fn(out);
          return !stopped;
        },
        sub);
    if (stopped) return;
    before += sizes_[i];
  }
  if (progress) progress(total, total);
}

}  // namespace

std::unique_ptr<BagReader> openBagDirectory(const fs::path& dir) { return std::make_unique<DirectoryReader>(dir); }

}  // namespace glassmap::ros2
