// libFuzzer: image bytes -> size check and decode (TGA/JPG/PNG/BMP...).
#include <cstddef>
#include <cstdint>
#include <span>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/image/image.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    // Header checks run for every input; full decodes are limited to 1 Mpixel to keep the
    // fuzzer fast (large sizes are the same code paths with longer loops).
    const auto [w, h] = q3::imageSize(bytes, "fuzz.img");
    if (static_cast<int64_t>(w) * h > (1 << 20)) return 0;
    const q3::Image image = q3::decodeImage(bytes, "fuzz.img");
    if (image.rgba.size() != static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * 4) __builtin_trap();
    (void)q3::averageColor(image);
  } catch (const q3::FormatError&) {
  }
  return 0;
}
