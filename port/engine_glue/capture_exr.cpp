#include "port/engine_glue/capture_exr.h"

#include <array>
#include <stdexcept>

#include "renderer/image_io/exr_writer.h"

namespace glue {

void FilmCapture::assign(const TracedPicture& picture) {
  clear();
  const size_t pixels = static_cast<size_t>(picture.filmWidth) * static_cast<size_t>(picture.filmHeight);
  if (pixels == 0 || picture.radiance.size() != pixels) return;
  width = picture.filmWidth;
  height = picture.filmHeight;
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
  std::array<std::vector<float>, 3> rgb;
  for (auto& plane : rgb) plane.resize(pixels);
  for (size_t i = 0; i < pixels; ++i)
    for (size_t c = 0; c < 3; ++c) rgb[c][i] = film.rgb[i * 3 + c];
  try {
    return pa::image_io::encodeExr(static_cast<uint32_t>(film.width), static_cast<uint32_t>(film.height),
                                   {{"R", rgb[0]}, {"G", rgb[1]}, {"B", rgb[2]}, {"variance.Y", film.variance}});
  } catch (const std::runtime_error&) {
    return {};
  }
}

}  // namespace glue
