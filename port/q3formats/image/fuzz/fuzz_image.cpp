// libFuzzer: image bytes -> size check and decode (TGA/JPG/PNG/BMP...).
#include <cstddef>
#include <cstdint>
#include <span>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/image/image.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    const q3::Image image = q3::decodeImage(bytes, "fuzz.img");
    if (image.rgba.size() != static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * 4) __builtin_trap();
    (void)q3::averageColor(image);
  } catch (const q3::FormatError&) {
  }
  return 0;
}
