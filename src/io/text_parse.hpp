#pragma once
// Private helpers of the text readers: fast tokenizing and strict number parsing with context.

#include <charconv>
#include <cstddef>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "glassmap/core/error.hpp"

namespace glassmap::io_detail {

/// ": <why>" when a filesystem check failed (a name too long, a permission), "" when it just said no.
inline std::string reason(const std::error_code& ec) { return ec ? ": " + ec.message() : std::string(); }

/// Splits a line on blanks (space, tab, CR) into views; clears `out` first.
inline void splitBlanks(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (i < n) {
    while (i < n && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    if (i == n) break;
    const std::size_t start = i;
    while (i < n && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    out.push_back(line.substr(start, i - start));
  }
}

/// Parses the whole token as a double (accepts inf/nan); false when it is not a number.
inline bool tryParseDouble(std::string_view tok, double& value) {
  if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
  if (tok.empty()) return false;
  const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), value);
  return ec == std::errc() && ptr == tok.data() + tok.size();
}

/// True when the token is a number.
inline bool isNumber(std::string_view tok) {
  double ignored = 0.0;
  return tryParseDouble(tok, ignored);
}

/// Where a line came from, for errors.
struct LineContext {
  const std::string* file = nullptr;
  std::size_t line = 0;

  [[noreturn]] void fail(const std::string& message, const std::string& field = {}) const {
    throw Error(message, file ? *file : std::string(), line, field);
  }

  double number(std::string_view tok, const std::string& field) const {
    double v = 0.0;
    if (!tryParseDouble(tok, v)) fail("expected a number, got '" + std::string(tok) + "'", field);
    return v;
  }

  long integer(std::string_view tok, const std::string& field) const {
    long v = 0;
    const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (ec != std::errc() || ptr != tok.data() + tok.size())
      fail("expected an integer, got '" + std::string(tok) + "'", field);
    return v;
  }
};

/// Appends the shortest decimal form that reads back to exactly `v`.
template <typename T>
inline void appendNumber(std::string& out, T v) {
  char buf[64];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, ec == std::errc() ? ptr : buf);
}

}  // namespace glassmap::io_detail
