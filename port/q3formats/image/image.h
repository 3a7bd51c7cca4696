#pragma once
// Image decoding for game textures into RGBA8: TGA, PNG and BMP via stb_image, JPEG via
// libjpeg-turbo (as the engine).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace q3 {

/// An 8-bit RGBA image, rows top to bottom.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  ///< width * height * 4 bytes

  /// The RGBA of pixel (x, y); x, y must be inside the image.
  std::array<uint8_t, 4> pixel(int x, int y) const {
    const size_t i = (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * 4;
    return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
  }
};

/// Limits checked on the header before any pixel is decoded.
struct ImageLimits {
  static constexpr int maxDimension = 8192;               ///< per side
  static constexpr size_t maxFileBytes = size_t{1} << 28;  ///< 256 MiB of encoded data
};

/// Decodes TGA (uncompressed and RLE; true-colour 16/24/32 bit, grey, colour-mapped; either
/// origin), JPG, PNG or BMP (other formats stb knows are refused). The size is read first and
/// refused beyond ImageLimits; failures throw FormatError naming `name` and the field. JPEGs
/// are decoded by libjpeg-turbo (renderer/image_codecs/jpeg_decode.h), the rest by stb_image.
/// The result is always RGBA8, top row first.
Image decodeImage(std::span<const std::byte> bytes, const std::string& name);

/// Width and height from the header only (no decode); throws FormatError if unreadable.
std::array<int, 2> imageSize(std::span<const std::byte> bytes, const std::string& name);

/// The texture to show for a missing or broken image: a magenta/black checkerboard of
/// `cells` x `cells` squares, `size` pixels wide (opaque).
Image fallbackImage(int size = 64, int cells = 8);

/// Mean colour of an image (each channel in [0, 1], not linearised), e.g. as the colour hint
/// of a q3map_lightimage. An empty image gives opaque white.
std::array<float, 4> averageColor(const Image& image);

}  // namespace q3
