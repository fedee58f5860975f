#include "mcap_compress.hpp"

#include <lz4frame.h>
#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "glassmap/core/error.hpp"

namespace glassmap::ros2 {
namespace {

constexpr std::uint64_t kFloorLimit = 64ull << 20;  // any stream may expand to this much [bytes]
constexpr std::uint64_t kRatioLimit = 256;          // beyond the floor: at most this ratio

std::uint64_t expansionLimit(std::size_t in_size) {
  return std::max<std::uint64_t>(kFloorLimit, kRatioLimit * in_size);
}

/// Grows `out` for the next decoder call: first to what a 16:1 ratio of `in_size` gives, then
/// doubling, capped at `limit`; false when at the cap.
bool grow(std::vector<std::uint8_t>& out, std::size_t used, std::uint64_t limit, std::size_t in_size) {
  if (used >= limit) return false;
  const std::uint64_t first = std::max<std::uint64_t>(64 << 10, 16 * static_cast<std::uint64_t>(in_size));
  const std::uint64_t want = std::min<std::uint64_t>(limit, used == 0 ? first : std::max<std::uint64_t>(used * 2, first));
  out.resize(static_cast<std::size_t>(want));
  return true;
}

/// Streams one zstd frame from `in` into `out` (resized to what came out), at most `limit` bytes.
/// Returns false when the output would exceed `limit`.
bool zstdStream(std::span<const std::uint8_t> in, std::vector<std::uint8_t>& out, std::uint64_t limit,
                const std::string& file, const std::string& where) {
  std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> ctx(ZSTD_createDCtx(), ZSTD_freeDCtx);
  if (!ctx) throw Error(where + ": out of memory for zstd", file);
  ZSTD_inBuffer src{in.data(), in.size(), 0};
  std::size_t used = 0;
  out.clear();
  for (;;) {
    if (used == out.size() && !grow(out, used, limit, in.size())) {
      // Full: the frame may still be complete (an exact fit) — check with an empty output.
      std::uint8_t probe = 0;
      ZSTD_outBuffer dst{&probe, 1, 0};
      const std::size_t r = ZSTD_decompressStream(ctx.get(), &dst, &src);
      if (ZSTD_isError(r)) throw Error(where + ": corrupt zstd data: " + ZSTD_getErrorName(r), file);
      if (dst.pos > 0) return false;
      if (r == 0) break;
      if (src.pos == src.size) throw Error(where + ": zstd data ends inside a frame", file);
      continue;
    }
    ZSTD_outBuffer dst{out.data(), out.size(), used};
    const std::size_t r = ZSTD_decompressStream(ctx.get(), &dst, &src);
    if (ZSTD_isError(r)) throw Error(where + ": corrupt zstd data: " + ZSTD_getErrorName(r), file);
    used = dst.pos;
    if (r == 0) break;  // frame complete
    if (src.pos == src.size && dst.pos < dst.size) throw Error(where + ": zstd data ends inside a frame", file);
  }
  if (src.pos != src.size) throw Error(where + ": bytes after the end of the zstd frame", file);
  out.resize(used);
  return true;
}

bool lz4Stream(std::span<const std::uint8_t> in, std::vector<std::uint8_t>& out, std::uint64_t limit,
               const std::string& file, const std::string& where) {
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION))) throw Error(where + ": lz4 init", file);
  std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> ctx(raw, LZ4F_freeDecompressionContext);
  std::size_t pos = 0, used = 0;
  out.clear();
  for (;;) {
    if (used == out.size() && !grow(out, used, limit, in.size())) {
      std::uint8_t probe = 0;
      std::size_t dst_size = 1, src_size = in.size() - pos;
      const std::size_t r = LZ4F_decompress(ctx.get(), &probe, &dst_size, in.data() + pos, &src_size, nullptr);
      if (LZ4F_isError(r)) throw Error(where + ": corrupt lz4 data: " + LZ4F_getErrorName(r), file);
      pos += src_size;
      if (dst_size > 0) return false;
      if (r == 0) break;
      if (pos == in.size()) throw Error(where + ": lz4 data ends inside a frame", file);
      continue;
    }
    std::size_t dst_size = out.size() - used, src_size = in.size() - pos;
    const std::size_t r = LZ4F_decompress(ctx.get(), out.data() + used, &dst_size, in.data() + pos, &src_size, nullptr);
    if (LZ4F_isError(r)) throw Error(where + ": corrupt lz4 data: " + LZ4F_getErrorName(r), file);
    pos += src_size;
    used += dst_size;
    if (r == 0) break;  // frame complete
    if (pos == in.size() && used < out.size()) throw Error(where + ": lz4 data ends inside a frame", file);
  }
  if (pos != in.size()) throw Error(where + ": bytes after the end of the lz4 frame", file);
  out.resize(used);
  return true;
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

FilePtr openFile(const std::filesystem::path& p, const char* mode) {
  FilePtr f(std::fopen(p.c_str(), mode));
  if (!f) throw Error(std::string("cannot open: ") + std::strerror(errno), p.string());
  return f;
}

}  // namespace

std::string compressionName(BagCompression c) {
  switch (c) {
    case BagCompression::Zstd: return "zstd";
    case BagCompression::Lz4: return "lz4";
    case BagCompression::None: break;
  }
  return "";
}

std::vector<std::uint8_t> compressBytes(BagCompression c, std::span<const std::uint8_t> in) {
  std::vector<std::uint8_t> out;
  if (c == BagCompression::Zstd) {
    out.resize(ZSTD_compressBound(in.size()));
    const std::size_t n = ZSTD_compress(out.data(), out.size(), in.data(), in.size(), 3);
    if (ZSTD_isError(n)) throw Error(std::string("zstd compression failed: ") + ZSTD_getErrorName(n));
    out.resize(n);
  } else if (c == BagCompression::Lz4) {
    LZ4F_preferences_t prefs{};
    prefs.frameInfo.contentSize = in.size();
    out.resize(LZ4F_compressFrameBound(in.size(), &prefs));
    const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), in.data(), in.size(), &prefs);
    if (LZ4F_isError(n)) throw Error(std::string("lz4 compression failed: ") + LZ4F_getErrorName(n));
    out.resize(n);
  } else {
    out.assign(in.begin(), in.end());
  }
  return out;
}

void decompressBytes(const std::string& name, std::span<const std::uint8_t> in, std::uint64_t expected,
                     std::vector<std::uint8_t>& out, const std::string& file, const std::string& where) {
  const auto mismatch = [&](std::uint64_t got) {
    return Error(where + ": " + (name.empty() ? "uncompressed" : name) + " data holds " + std::to_string(got) +
                     " bytes, the record says " + std::to_string(expected),
                 file);
  };
  if (name.empty()) {
    if (in.size() != expected) throw mismatch(in.size());
    out.assign(in.begin(), in.end());
    return;
  }
  if (name != "zstd" && name != "lz4") throw Error(where + ": unknown compression '" + name + "'", file);
  if (expected > expansionLimit(in.size()))
    throw Error(where + ": implausible uncompressed size " + std::to_string(expected) + " for " +
                    std::to_string(in.size()) + " compressed bytes",
                file);
  const bool fits =
      name == "zstd" ? zstdStream(in, out, expected, file, where) : lz4Stream(in, out, expected, file, where);
  if (!fits)
    throw Error(where + ": " + name + " data expands beyond the declared " + std::to_string(expected) + " bytes", file);
  if (out.size() != expected) throw mismatch(out.size());
}

void zstdDecompressAny(std::span<const std::uint8_t> in, std::vector<std::uint8_t>& out, const std::string& file,
                       const std::string& where) {
  const std::uint64_t limit = expansionLimit(in.size());
  if (!zstdStream(in, out, limit, file, where))
    throw Error(where + ": zstd data expands beyond " + std::to_string(limit) + " bytes", file);
}

void zstdDecompressFile(const std::filesystem::path& in, const std::filesystem::path& out) {
  auto src = openFile(in, "rb");
  auto dst = openFile(out, "wb");
  std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> ctx(ZSTD_createDCtx(), ZSTD_freeDCtx);
  std::vector<char> ibuf(ZSTD_DStreamInSize()), obuf(ZSTD_DStreamOutSize());
  std::uint64_t read_total = 0;
  std::size_t last = 0;
  bool any = false;
  while (std::size_t n = std::fread(ibuf.data(), 1, ibuf.size(), src.get())) {
    any = true;
    ZSTD_inBuffer ib{ibuf.data(), n, 0};
    while (ib.pos < ib.size) {
      ZSTD_outBuffer ob{obuf.data(), obuf.size(), 0};
      last = ZSTD_decompressStream(ctx.get(), &ob, &ib);
      if (ZSTD_isError(last))
        throw Error(
            "corrupt zstd data near byte " + std::to_string(read_total + ib.pos) + ": " + ZSTD_getErrorName(last),
            in.string());
      if (std::fwrite(obuf.data(), 1, ob.pos, dst.get()) != ob.pos)
        throw Error(std::string("cannot write: ") + std::strerror(errno), out.string());
    }
    read_total += n;
  }
  if (std::ferror(src.get())) throw Error(std::string("cannot read: ") + std::strerror(errno), in.string());
  if (!any || last != 0)
    throw Error("zstd data ends inside a frame at byte " + std::to_string(read_total), in.string());
  if (std::fflush(dst.get()) != 0) throw Error(std::string("cannot write: ") + std::strerror(errno), out.string());
}

void zstdCompressFile(const std::filesystem::path& in, const std::filesystem::path& out) {
  auto src = openFile(in, "rb");
  auto dst = openFile(out, "wb");
  std::unique_ptr<ZSTD_CCtx, decltype(&ZSTD_freeCCtx)> ctx(ZSTD_createCCtx(), ZSTD_freeCCtx);
  std::vector<char> ibuf(ZSTD_CStreamInSize()), obuf(ZSTD_CStreamOutSize());
  const auto put = [&](const ZSTD_outBuffer& ob) {
    if (std::fwrite(obuf.data(), 1, ob.pos, dst.get()) != ob.pos)
      throw Error(std::string("cannot write: ") + std::strerror(errno), out.string());
  };
  for (;;) {
    const std::size_t n = std::fread(ibuf.data(), 1, ibuf.size(), src.get());
    const bool last = n < ibuf.size();
    ZSTD_inBuffer ib{ibuf.data(), n, 0};
    for (;;) {
      ZSTD_outBuffer ob{obuf.data(), obuf.size(), 0};
      const std::size_t r = ZSTD_compressStream2(ctx.get(), &ob, &ib, last ? ZSTD_e_end : ZSTD_e_continue);
      if (ZSTD_isError(r)) throw Error(std::string("zstd compression failed: ") + ZSTD_getErrorName(r), in.string());
      put(ob);
      if (last ? r == 0 : ib.pos == ib.size) break;
    }
    if (last) break;
  }
  if (std::ferror(src.get())) throw Error(std::string("cannot read: ") + std::strerror(errno), in.string());
  if (std::fflush(dst.get()) != 0) throw Error(std::string("cannot write: ") + std::strerror(errno), out.string());
}

}  // namespace glassmap::ros2
