#pragma once
// JPEG decoding with libjpeg-turbo (the library the engine's stock renderer uses), used by
// image.cpp in place of stb_image for every JPEG.
#include <array>
#include <cstddef>
#include <span>
#include <string>

#include "port/q3formats/image/image.h"

namespace q3 {

/// True when the bytes start with a JPEG's SOI marker followed by another marker.
bool isJpeg(std::span<const std::byte> bytes);

/// Width and height from the JPEG's headers (up to its first scan); throws FormatError with
/// libjpeg's message when they cannot be read.
std::array<int, 2> jpegSize(std::span<const std::byte> bytes, const std::string& name);

/// Decodes a baseline or progressive JPEG (grey, YCbCr, RGB, CMYK or YCCK) to RGBA8 (alpha 255),
/// top row first, with libjpeg's default (accurate integer) IDCT and fancy upsampling. Sizes
/// beyond ImageLimits and files of more than JpegLimits::maxScans scans are refused before the
/// pixels are decoded; libjpeg's errors throw FormatError naming `name`. Corrupt entropy-coded
/// data is decoded as libjpeg decodes it for the engine (its warnings are not errors).
Image decodeJpeg(std::span<const std::byte> bytes, const std::string& name);

/// Limits on work for a JPEG, besides ImageLimits.
struct JpegLimits {
  /// Progressive files with many scans make each scan pass over the whole image; real textures
  /// have at most a few dozen.
  static constexpr int maxScans = 256;
};

}  // namespace q3
