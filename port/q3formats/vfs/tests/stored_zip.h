#pragma once
// Test helper: writes minimal "stored" (uncompressed) zip archives, enough for physfs.
#include <cstdint>
#include <filesystem>
#include <gtest/gtest.h>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace q3::test {

inline uint32_t crc32(const std::string& data) {
  uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char c : data) {
    crc ^= c;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

/// The bytes of a zip file holding `entries` (name, contents) with no compression.
inline std::string storedZip(const std::vector<std::pair<std::string, std::string>>& entries) {
  std::string out, central;
  auto u16 = [](std::string& s, uint16_t v) { s.push_back(char(v & 0xFF)), s.push_back(char(v >> 8)); };
  auto u32 = [&](std::string& s, uint32_t v) { u16(s, uint16_t(v & 0xFFFF)), u16(s, uint16_t(v >> 16)); };
  for (const auto& [name, data] : entries) {
    const uint32_t offset = static_cast<uint32_t>(out.size());
    const uint32_t crc = crc32(data), size = static_cast<uint32_t>(data.size());
    u32(out, 0x04034b50); u16(out, 10); u16(out, 0); u16(out, 0); u16(out, 0); u16(out, 0x21);
    u32(out, crc); u32(out, size); u32(out, size); u16(out, uint16_t(name.size())); u16(out, 0);
    out += name;
    out += data;
    u32(central, 0x02014b50); u16(central, 20); u16(central, 10); u16(central, 0); u16(central, 0);
    u16(central, 0); u16(central, 0x21); u32(central, crc); u32(central, size); u32(central, size);
    u16(central, uint16_t(name.size())); u16(central, 0); u16(central, 0); u16(central, 0); u16(central, 0);
    u32(central, 0); u32(central, offset);
    central += name;
  }
  const uint32_t centralOffset = static_cast<uint32_t>(out.size());
  out += central;
  u32(out, 0x06054b50); u16(out, 0); u16(out, 0); u16(out, uint16_t(entries.size()));
  u16(out, uint16_t(entries.size())); u32(out, static_cast<uint32_t>(central.size()));
  u32(out, centralOffset); u16(out, 0);
  return out;
}

/// Writes `entries` (name, contents) as a zip file with no compression.
inline void writeStoredZip(const std::filesystem::path& file,
                           const std::vector<std::pair<std::string, std::string>>& entries) {
  const std::string out = storedZip(entries);
  std::ofstream(file, std::ios::binary).write(out.data(), static_cast<std::streamsize>(out.size()));
}

/// A fresh temporary folder, removed on destruction.
class TempDir {
 public:
  explicit TempDir(const std::string& tag) {
    path_ = std::filesystem::temp_directory_path() /
            ("patharena_" + tag + "_" + std::to_string(reinterpret_cast<uintptr_t>(this)) + "_" +
             std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace q3::test
