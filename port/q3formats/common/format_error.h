#pragma once
// The one error type of the formats library: which file, which field, what was wrong.
#include <stdexcept>
#include <string>

namespace q3 {

/// Thrown by every parser on malformed input. what() reads "FILE: FIELD: DETAIL".
class FormatError : public std::runtime_error {
 public:
  FormatError(std::string file, std::string field, const std::string& detail)
      : std::runtime_error(file + ": " + field + ": " + detail),
        file_(std::move(file)),
        field_(std::move(field)) {}
  /// Name of the file being parsed (as given by the caller).
  const std::string& file() const { return file_; }
  /// The field or structure that failed the check (e.g. "lump 13 (surfaces)").
  const std::string& field() const { return field_; }

 private:
  std::string file_;
  std::string field_;
};

}  // namespace q3
