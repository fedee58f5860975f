#pragma once
/// Error type that carries where bad input was found: file, line and field.

#include <cstddef>
#include <stdexcept>
#include <string>

namespace glassmap {

/// Input or processing error. what() reads "file:line: field: message" with the parts known.
class Error : public std::runtime_error {
 public:
  explicit Error(std::string message, std::string file = {}, std::size_t line = 0, std::string field = {});

  const std::string& message() const { return message_; }  ///< the bare message
  const std::string& file() const { return file_; }        ///< input file, empty if none
  std::size_t line() const { return line_; }               ///< 1-based line, 0 if none
  const std::string& field() const { return field_; }      ///< field name, empty if none

 private:
  std::string message_, file_;
  std::size_t line_ = 0;
  std::string field_;
};

}  // namespace glassmap
