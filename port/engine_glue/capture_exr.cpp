#include "port/engine_glue/capture_exr.h"

#include <array>
#include <cstdlib>
#include <cstring>

#include <tinyexr.h>

namespace glue {

void FilmCapture::assign(const TracedPicture& picture) {
  clear();
  const size_t pixels = static_cast<size_t>(picture.width) * static_cast<size_t>(picture.height);
  if (pixels == 0 || picture.radiance.size() != pixels) return;
  width = picture.width;
  height = picture.height;
  rgb.resize(pixels * 3);
  for (size_t i = 0; i < pixels; ++i)
    for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = picture.radiance[i][c];
  variance.assign(pixels, 0.0f);
  if (picture.variance.size() == pixels) variance.assign(picture.variance.begin(), picture.variance.end());
}

void FilmCapture::clear() {
  width = height = 0;
  rgb.clear();
  variance.clear();
}

std::vector<uint8_t> encodeFilmExr(const FilmCapture& film) {
  const size_t pixels = static_cast<size_t>(film.width) * static_cast<size_t>(film.height);
  if (pixels == 0 || film.rgb.size() != pixels * 3 || film.variance.size() != pixels) return {};
  // Channels sorted by name, as EXR readers expect: B, G, R, variance.Y.
  std::array<std::vector<float>, 4> planes;
  for (auto& plane : planes) plane.resize(pixels);
  for (size_t i = 0; i < pixels; ++i) {
    planes[0][i] = film.rgb[i * 3 + 2];
    planes[1][i] = film.rgb[i * 3 + 1];
    planes[2][i] = film.rgb[i * 3 + 0];
    planes[3][i] = film.variance[i];
  }
  const std::array<const char*, 4> names = {"B", "G", "R", "variance.Y"};
  std::array<EXRChannelInfo, 4> infos{};
  std::array<int, 4> types{};
  std::array<unsigned char*, 4> images{};
  for (size_t c = 0; c < 4; ++c) {
    std::strncpy(infos[c].name, names[c], sizeof(infos[c].name) - 1);
    types[c] = TINYEXR_PIXELTYPE_FLOAT;
    images[c] = reinterpret_cast<unsigned char*>(planes[c].data());
  }
  EXRHeader header;
  InitEXRHeader(&header);
  header.num_channels = 4;
  header.channels = infos.data();
  header.pixel_types = types.data();
  header.requested_pixel_types = types.data();
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
  EXRImage image;
  InitEXRImage(&image);
  image.num_channels = 4;
  image.images = images.data();
  image.width = film.width;
  image.height = film.height;
  unsigned char* memory = nullptr;
  const char* error = nullptr;
  const size_t size = SaveEXRImageToMemory(&image, &header, &memory, &error);
  if (error != nullptr) FreeEXRErrorMessage(error);
  std::vector<uint8_t> out;
  if (size > 0 && memory != nullptr) out.assign(memory, memory + size);
  std::free(memory);
  return out;
}

}  // namespace glue
