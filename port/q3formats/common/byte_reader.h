#pragma once
// Bounds-checked little-endian reads from an untrusted byte buffer.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>

#include "port/q3formats/common/format_error.h"

namespace q3 {

/// Reads trivially copyable values from a byte span; every access is checked and a
/// failure throws FormatError naming the file and the field. Assumes a little-endian host.
class ByteReader {
 public:
  ByteReader(std::span<const std::byte> bytes, std::string file)
      : bytes_(bytes), file_(std::move(file)) {}

  /// Total size of the buffer.
  size_t size() const { return bytes_.size(); }
  /// Name used in error messages.
  const std::string& file() const { return file_; }

  /// Throws unless [offset, offset + count * elemSize) lies inside the buffer (overflow-safe).
  void require(size_t offset, size_t count, size_t elemSize, const char* field) const {
    if (elemSize != 0 && count > (SIZE_MAX / elemSize)) fail(field, "element count overflows");
    const size_t len = count * elemSize;
    if (offset > bytes_.size() || len > bytes_.size() - offset)
      fail(field, "range [" + std::to_string(offset) + ", +" + std::to_string(len) +
                      ") outside file of " + std::to_string(bytes_.size()) + " bytes");
  }

  /// One value of type T at a byte offset.
  template <class T>
  T read(size_t offset, const char* field) const {
    static_assert(std::is_trivially_copyable_v<T>);
    require(offset, 1, sizeof(T), field);
    T value;
    std::memcpy(&value, bytes_.data() + offset, sizeof(T));
    return value;
  }

  /// A view of `count` bytes at `offset`.
  std::span<const std::byte> bytes(size_t offset, size_t count, const char* field) const {
    require(offset, count, 1, field);
    return bytes_.subspan(offset, count);
  }

  /// A fixed-size, possibly unterminated, char field as a string (stops at the first NUL).
  std::string fixedString(size_t offset, size_t capacity, const char* field) const {
    auto raw = bytes(offset, capacity, field);
    size_t n = 0;
    while (n < capacity && raw[n] != std::byte{0}) ++n;
    return std::string(reinterpret_cast<const char*>(raw.data()), n);
  }

  /// Throws FormatError(file, field, detail).
  [[noreturn]] void fail(const char* field, const std::string& detail) const {
    throw FormatError(file_, field, detail);
  }

 private:
  std::span<const std::byte> bytes_;
  std::string file_;
};

}  // namespace q3
