#pragma once
// What the measurement tools (pa-denoise-timing, pa-temporal-timing) share: their numeric
// arguments and a hash of their output bytes, to tell whether two builds compute the same.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>

namespace pa::timing {

/// argv[i] as an unsigned number, or `fallback` when there are fewer arguments.
inline uint32_t argOr(int argc, char** argv, int i, uint32_t fallback) {
  return argc > i ? static_cast<uint32_t>(std::strtoul(argv[i], nullptr, 10)) : fallback;
}

/// The FNV-1a offset basis: the hash of no bytes.
inline constexpr uint64_t kHashStart = 1469598103934665603ull;

/// FNV-1a of `h` continued over the bytes of the values.
template <typename T>
uint64_t hashBytes(uint64_t h, std::span<const T> values) {
  for (const T& v : values) {
    unsigned char bytes[sizeof v];
    std::memcpy(bytes, &v, sizeof v);
    for (unsigned char b : bytes) h = (h ^ b) * 1099511628211ull;
  }
  return h;
}

}  // namespace pa::timing
