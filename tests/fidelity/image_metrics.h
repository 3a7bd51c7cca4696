// Full-reference image quality metrics for frame-capture regression tests:
// PSNR over RGB and SSIM (Wang, Bovik, Sheikh, Simoncelli 2004) on luma.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace pa::fidelity {

/// An 8-bit RGB image, rows top to bottom, 3 bytes per pixel.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  ///< width * height * 3 bytes
};

/// Reads a PNG/TGA/JPEG (anything stb_image decodes) as RGB; throws std::runtime_error naming the file.
RgbImage loadRgb(const std::string& path);

/// Writes an RGB image as PNG; throws std::runtime_error naming the file.
void savePng(const std::string& path, const RgbImage& image);

/// The two images' comparison figures.
struct Comparison {
  double mse = 0;        ///< mean squared error over all R, G, B samples (0..255 scale)
  double psnr = 0;       ///< 10 log10(255^2 / mse) in dB; +infinity when the images are identical
  double ssim = 0;       ///< mean SSIM over every 11x11 window lying fully inside the luma image
  double maxAbsDiff = 0; ///< largest per-sample absolute difference (0..255)
};

/// Luma Y = 0.299 R + 0.587 G + 0.114 B (ITU-R BT.601) of each pixel, as doubles in 0..255.
std::vector<double> luma(const RgbImage& image);

/// SSIM of two luma planes of the same size: Gaussian window 11x11, sigma 1.5 (normalised),
/// K1 = 0.01, K2 = 0.03, L = 255, averaged over the windows fully inside the image (no padding),
/// as in Wang et al. 2004. Throws std::invalid_argument when the planes are smaller than 11x11.
double ssimLuma(std::span<const double> a, std::span<const double> b, int width, int height);

/// Compares two images of the same size; throws std::invalid_argument when the sizes differ.
Comparison compare(const RgbImage& a, const RgbImage& b);

/// The square tile of a tiling where two images differ most (largest mean squared error).
struct WorstTile {
  int x = 0;          ///< left column of the tile
  int y = 0;          ///< top row of the tile
  int size = 0;       ///< tile edge in pixels (edge tiles are cut to the image)
  double mse = 0;     ///< mean squared error over the tile's R, G, B samples
  double psnr = 0;    ///< the tile's PSNR in dB; +infinity when the tile is identical
};

/// Cuts both images into size x size tiles from the top-left corner (the last row and column
/// cut to the image) and returns the tile with the largest MSE (the first such tile in row order).
/// Throws std::invalid_argument when the sizes differ or size < 1.
WorstTile worstTile(const RgbImage& a, const RgbImage& b, int size);

/// The width x height rectangle of `image` whose top-left pixel is (x, y); throws
/// std::invalid_argument when the rectangle is empty or not inside the image.
RgbImage crop(const RgbImage& image, int x, int y, int width, int height);

/// Mean linear luminance of the image in [0, 1]: each 8-bit channel sRGB-decoded, then
/// Y = 0.2126 R + 0.7152 G + 0.0722 B (ITU-R BT.709). What "as bright as" compares.
double meanLinearLuminance(const RgbImage& image);

/// Per-pixel absolute difference |a - b| per channel, multiplied by gain and clamped to 255.
RgbImage differenceImage(const RgbImage& a, const RgbImage& b, double gain);

}  // namespace pa::fidelity
