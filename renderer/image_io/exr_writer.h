#pragma once
// OpenEXR encoding (tinyexr) of float planes: pa-render's --exr and the game module's film
// capture write their files through it.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace pa::image_io {

/// One named plane of width * height 32-bit floats, top row first.
struct ExrChannel {
  std::string name;               ///< EXR channel name, e.g. "R" or "albedo.G".
  std::span<const float> values;  ///< width * height values.
};

/// Single-part scanline OpenEXR bytes (32-bit float, ZIP) holding `channels`, written in name
/// order as EXR readers expect. Throws std::runtime_error when the size is 0, a plane's length
/// is not width * height, or tinyexr fails (its message).
std::vector<uint8_t> encodeExr(uint32_t width, uint32_t height, std::vector<ExrChannel> channels);

}  // namespace pa::image_io
