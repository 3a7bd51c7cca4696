#pragma once
// The world view's film kept for screenshots when r_pt_captureExr is on, and its OpenEXR bytes:
// tests/regress checks Monte Carlo game frames noise-aware from each pixel's mean and variance.
#include <cstdint>
#include <vector>

#include "port/engine_glue/views.h"

namespace glue {

/// A copy of one traced view's film: linear radiance and the variance of each pixel's mean luminance.
struct FilmCapture {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;        ///< width * height * 3 linear radiance values, top row first.
  std::vector<float> variance;   ///< width * height variances of the mean luminance (0 when unknown).

  /// Copies the film behind `picture` (nothing when it has none).
  void assign(const TracedPicture& picture);
  /// Forgets the copy (keeps the memory).
  void clear();
  /// True when no film is held.
  bool empty() const { return rgb.empty(); }
};

/// Single-part scanline OpenEXR bytes (32-bit float, ZIP) with channels R, G, B and variance.Y, as
/// pa-render's --exr names them; empty when the film is empty or encoding failed.
std::vector<uint8_t> encodeFilmExr(const FilmCapture& film);

}  // namespace glue
