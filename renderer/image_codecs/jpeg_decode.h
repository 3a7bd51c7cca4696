#pragma once
// JPEG decoding with libjpeg-turbo (the library ioquake3's stock renderer uses), for game
// textures and glTF images alike. stb_image 2.27 is not used for JPEGs: a corrupt baseline
// stream drives its bit count negative (port/q3formats/FUZZING.md, image finding 6).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace pa {

/// An 8-bit RGBA image, rows top to bottom, alpha 255.
struct JpegImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  ///< width * height * 4 bytes
};

/// Limits on what a JPEG may make the decoder do.
struct JpegLimits {
  int maxDimension = 8192;  ///< per side, checked on the header before any pixel is decoded
  /// Progressive files with many scans make each scan pass over the whole image; real images
  /// have at most a few dozen.
  int maxScans = 256;
};

/// A JPEG that cannot be decoded: libjpeg's message, or the limit it broke.
class JpegError : public std::runtime_error {
 public:
  /// Where it failed.
  enum class Stage { Header, Size, Data };
  JpegError(Stage stage, const std::string& message) : std::runtime_error(message), stage_(stage) {}
  /// Header (the markers up to the first scan), Size (over JpegLimits) or Data (the scans).
  Stage stage() const { return stage_; }

 private:
  Stage stage_;
};

/// True when the bytes start with a JPEG's SOI marker followed by another marker.
bool isJpeg(std::span<const std::byte> bytes);

/// Width and height from the headers (up to the first scan); throws JpegError when they cannot
/// be read.
std::array<int, 2> jpegSize(std::span<const std::byte> bytes);

/// Decodes a baseline or progressive JPEG (grey, YCbCr, RGB, CMYK or YCCK) to RGBA8 with
/// libjpeg's defaults (accurate integer IDCT, fancy upsampling), as the engine decodes textures.
/// Sizes and scan counts beyond `limits` are refused. Errors throw JpegError; exceptions never
/// cross libjpeg's frames (its error exit jumps back with longjmp). Corrupt entropy-coded data is
/// decoded as libjpeg decodes it for the engine: its warnings are not errors.
JpegImage decodeJpeg(std::span<const std::byte> bytes, const JpegLimits& limits = {});

}  // namespace pa
