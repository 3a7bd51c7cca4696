#include "port/q3formats/image/image.h"

#include <stb_image.h>

#include <climits>
#include <memory>

#include "port/q3formats/common/format_error.h"
#include "renderer/image_codecs/jpeg_decode.h"

namespace q3 {
namespace {

const stbi_uc* data(std::span<const std::byte> bytes) { return reinterpret_cast<const stbi_uc*>(bytes.data()); }

void checkInputSize(std::span<const std::byte> bytes, const std::string& name) {
  if (bytes.empty()) throw FormatError(name, "image", "empty file");
  if (bytes.size() > ImageLimits::maxFileBytes || bytes.size() > static_cast<size_t>(INT_MAX))
    throw FormatError(name, "image", "file of " + std::to_string(bytes.size()) + " bytes is too large");
}

std::string failureReason() {
  const char* why = stbi_failure_reason();
  return why ? why : "unknown reason";
}

uint8_t at(std::span<const std::byte> bytes, size_t i) { return static_cast<uint8_t>(bytes[i]); }

/// stb_image reads zeros past the end of a TGA, so a 45-byte file can claim 8192x8192 and make it
/// allocate and fill 256 MiB. Refuse a TGA shorter than its pixels need: exact for uncompressed
/// files, a lower bound for RLE (a packet covers at most 128 pixels with 1 + pixel-size bytes).
void checkTgaLength(std::span<const std::byte> bytes, int w, int h, const std::string& name) {
  if (bytes.size() < 18) return;
  const bool otherFormat = (at(bytes, 0) == 0x89 && at(bytes, 1) == 'P') ||
                           (at(bytes, 0) == 0xFF && at(bytes, 1) == 0xD8) ||
                           (at(bytes, 0) == 'B' && at(bytes, 1) == 'M');
  const uint8_t type = at(bytes, 2);
  const bool rle = type >= 9 && type <= 11;
  if (otherFormat || !((type >= 1 && type <= 3) || rle)) return;
  const size_t idLength = at(bytes, 0);
  const size_t mapLength = at(bytes, 1) ? (at(bytes, 5) | (at(bytes, 6) << 8)) : 0;
  const size_t mapEntryBytes = (at(bytes, 7) + 7u) / 8u;
  const size_t pixelBytes = (at(bytes, 16) + 7u) / 8u;
  const size_t pixels = static_cast<size_t>(w) * static_cast<size_t>(h);
  const size_t pixelData = rle ? (pixels + 127) / 128 * (1 + pixelBytes) : pixels * pixelBytes;
  const size_t need = 18 + idLength + mapLength * mapEntryBytes + pixelData;
  if (bytes.size() < need)
    throw FormatError(name, "TGA pixel data",
                      std::string("truncated: ") + std::to_string(bytes.size()) + " bytes, " +
                          (rle ? "at least " : "") + std::to_string(need) + " needed");
}

/// A JPEG failure as a FormatError naming the file and the stage.
[[noreturn]] void throwJpegError(const pa::JpegError& e, const std::string& name) {
  const char* field = e.stage() == pa::JpegError::Stage::Header ? "JPEG header"
                      : e.stage() == pa::JpegError::Stage::Size ? "image size"
                                                                 : "JPEG data";
  throw FormatError(name, field, e.what());
}

/// Only the formats the engine loads are decoded (stb also decodes GIF, PSD, PIC, PNM and HDR,
/// which would widen what a hostile pk3 can reach). PNG, JPEG and BMP are known by their magic numbers;
/// anything else must have a plausible TGA header (no other format's magic can pass that test).
void checkFormatIsAllowed(std::span<const std::byte> bytes, const std::string& name) {
  if (bytes.size() >= 8 && at(bytes, 0) == 0x89 && at(bytes, 1) == 'P' && at(bytes, 2) == 'N' && at(bytes, 3) == 'G') return;
  if (bytes.size() >= 3 && at(bytes, 0) == 0xFF && at(bytes, 1) == 0xD8 && at(bytes, 2) == 0xFF) return;
  if (bytes.size() >= 2 && at(bytes, 0) == 'B' && at(bytes, 1) == 'M') return;
  if (bytes.size() >= 18) {
    const uint8_t mapType = at(bytes, 1), type = at(bytes, 2), bpp = at(bytes, 16);
    const bool tgaType = type == 1 || type == 2 || type == 3 || type == 9 || type == 10 || type == 11;
    const bool tgaBpp = bpp == 8 || bpp == 15 || bpp == 16 || bpp == 24 || bpp == 32;
    if (mapType <= 1 && tgaType && tgaBpp) return;
  }
  throw FormatError(name, "image format", "not a TGA, JPEG, PNG or BMP file");
}

}  // namespace

std::array<int, 2> imageSize(std::span<const std::byte> bytes, const std::string& name) {
  checkInputSize(bytes, name);
  checkFormatIsAllowed(bytes, name);
  if (pa::isJpeg(bytes)) {
    try {
      return pa::jpegSize(bytes);
    } catch (const pa::JpegError& e) {
      throwJpegError(e, name);
    }
  }
  int w = 0, h = 0, comp = 0;
  if (!stbi_info_from_memory(data(bytes), static_cast<int>(bytes.size()), &w, &h, &comp))
    throw FormatError(name, "image header", "unreadable: " + failureReason());
  return {w, h};
}

Image decodeImage(std::span<const std::byte> bytes, const std::string& name) {
  checkInputSize(bytes, name);
  checkFormatIsAllowed(bytes, name);
  if (pa::isJpeg(bytes)) {  // libjpeg-turbo, as the engine
    try {
      pa::JpegImage jpeg = pa::decodeJpeg(bytes, {.maxDimension = ImageLimits::maxDimension});
      return Image{jpeg.width, jpeg.height, std::move(jpeg.rgba)};
    } catch (const pa::JpegError& e) {
      throwJpegError(e, name);
    }
  }
  const auto [w, h] = imageSize(bytes, name);
  if (w <= 0 || h <= 0 || w > ImageLimits::maxDimension || h > ImageLimits::maxDimension)
    throw FormatError(name, "image size",
                      std::to_string(w) + "x" + std::to_string(h) + " outside 1.." +
                          std::to_string(ImageLimits::maxDimension));
  checkTgaLength(bytes, w, h, name);
  int dw = 0, dh = 0, comp = 0;
  std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
      stbi_load_from_memory(data(bytes), static_cast<int>(bytes.size()), &dw, &dh, &comp, 4), stbi_image_free);
  if (!pixels) throw FormatError(name, "image data", "cannot decode: " + failureReason());
  if (dw != w || dh != h)
    throw FormatError(name, "image size", "header and decoded sizes differ");
  Image image;
  image.width = w;
  image.height = h;
  image.rgba.assign(pixels.get(), pixels.get() + static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
  return image;
}

Image fallbackImage(int size, int cells) {
  if (size < 1) size = 1;
  if (cells < 1) cells = 1;
  Image image;
  image.width = image.height = size;
  image.rgba.resize(static_cast<size_t>(size) * static_cast<size_t>(size) * 4);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const bool magenta = ((x * cells / size) + (y * cells / size)) % 2 == 0;
      uint8_t* p = &image.rgba[(static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x)) * 4];
      p[0] = magenta ? 255 : 0;
      p[1] = 0;
      p[2] = magenta ? 255 : 0;
      p[3] = 255;
    }
  return image;
}

std::array<float, 4> averageColor(const Image& image) {
  const size_t n = image.rgba.size() / 4;
  if (n == 0) return {1, 1, 1, 1};
  std::array<double, 4> sum{};
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 4; ++c) sum[c] += image.rgba[i * 4 + c];
  std::array<float, 4> mean;
  for (int c = 0; c < 4; ++c) mean[c] = static_cast<float>(sum[c] / (255.0 * static_cast<double>(n)));
  return mean;
}

}  // namespace q3
