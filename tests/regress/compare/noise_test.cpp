#include "tests/regress/compare/noise_test.h"

#include <tinyexr.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pa::regress {

HdrImage loadExr(const std::string& path) {
  EXRVersion version;
  if (ParseEXRVersionFromFile(&version, path.c_str()) != TINYEXR_SUCCESS)
    throw std::runtime_error(path + ": not an OpenEXR file");
  EXRHeader header;
  InitEXRHeader(&header);
  const char* error = nullptr;
  if (ParseEXRHeaderFromFile(&header, &version, path.c_str(), &error) != TINYEXR_SUCCESS) {
    std::string message = path + ": " + (error ? error : "bad EXR header");
    FreeEXRErrorMessage(error);
    throw std::runtime_error(message);
  }
  for (int c = 0; c < header.num_channels; ++c) header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
  EXRImage image;
  InitEXRImage(&image);
  if (LoadEXRImageFromFile(&image, &header, path.c_str(), &error) != TINYEXR_SUCCESS) {
    std::string message = path + ": " + (error ? error : "cannot read EXR pixels");
    FreeEXRErrorMessage(error);
    FreeEXRHeader(&header);
    throw std::runtime_error(message);
  }
  HdrImage out;
  out.width = image.width;
  out.height = image.height;
  const size_t n = static_cast<size_t>(image.width) * image.height;
  out.rgb.assign(3 * n, 0.0f);
  out.varianceY.assign(n, 0.0f);
  bool found[4] = {false, false, false, false};
  for (int c = 0; c < header.num_channels; ++c) {
    const std::string name = header.channels[c].name;
    const float* data = reinterpret_cast<const float*>(image.images[c]);
    int slot = name == "R" ? 0 : name == "G" ? 1 : name == "B" ? 2 : name == "variance.Y" ? 3 : -1;
    if (slot < 0) continue;
    found[slot] = true;
    for (size_t i = 0; i < n; ++i) {
      if (slot < 3) out.rgb[3 * i + slot] = data[i];
      else out.varianceY[i] = data[i];
    }
  }
  FreeEXRImage(&image);
  FreeEXRHeader(&header);
  if (!(found[0] && found[1] && found[2] && found[3]))
    throw std::runtime_error(path + ": needs channels R, G, B and variance.Y (pa-render --exr)");
  return out;
}

float luminanceAt(const HdrImage& image, size_t i) {
  return 0.2126f * image.rgb[3 * i] + 0.7152f * image.rgb[3 * i + 1] + 0.0722f * image.rgb[3 * i + 2];
}

double twoSidedCriticalZ(double p) {
  if (!(p > 0 && p < 1)) throw std::invalid_argument("twoSidedCriticalZ: p must lie in (0, 1)");
  // P(|Z| > z) = erfc(z / sqrt 2) decreases in z: bisect on [0, 40].
  double lo = 0, hi = 40;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

NoiseTestResult noiseTest(const HdrImage& test, const HdrImage& reference, const NoiseTestSettings& settings) {
  if (test.width != reference.width || test.height != reference.height)
    throw std::invalid_argument("noiseTest: image sizes differ");
  NoiseTestResult r;
  r.pixels = static_cast<size_t>(test.width) * test.height;
  if (r.pixels == 0) return r;
  // Sidak: with independent pixels, each at level pixelAlpha, the chance that any pixel of an
  // unchanged image fails is exactly the scale's share of alpha.
  const double scaleAlpha = settings.alpha / static_cast<double>(1 + settings.tileSizes.size());
  auto sidak = [&](size_t tests) { return -std::expm1(std::log1p(-scaleAlpha) / static_cast<double>(tests)); };
  r.pixelAlpha = sidak(r.pixels);
  r.zThreshold = twoSidedCriticalZ(r.pixelAlpha);
  r.z.resize(r.pixels);
  double sumZ = 0;
  for (size_t i = 0; i < r.pixels; ++i) {
    const double d = static_cast<double>(luminanceAt(test, i)) - luminanceAt(reference, i);
    const double v = static_cast<double>(test.varianceY[i]) + reference.varianceY[i];
    double z = 0;
    if (v > 0) z = std::abs(d) / std::sqrt(v);
    else if (d != 0) z = std::numeric_limits<double>::infinity();  // a noiseless pixel changed
    r.z[i] = static_cast<float>(z);
    if (!(z <= r.zThreshold)) ++r.failedPixels;
    sumZ += std::isfinite(z) ? z : r.zThreshold * 10;
  }
  r.meanAbsZ = sumZ / static_cast<double>(r.pixels);
  r.passFraction = 1.0 - static_cast<double>(r.failedPixels) / static_cast<double>(r.pixels);
  r.pass = r.passFraction >= settings.minPassFraction;

  for (int size : settings.tileSizes) {
    const int side = size > 0 ? size : std::max(test.width, test.height);
    const int tilesX = (test.width + side - 1) / side, tilesY = (test.height + side - 1) / side;
    TileScaleResult s;
    s.tileSize = size;
    s.tiles = static_cast<size_t>(tilesX) * tilesY;
    s.zThreshold = twoSidedCriticalZ(sidak(s.tiles));
    std::vector<double> diff(s.tiles, 0.0), var(s.tiles, 0.0);
    for (int y = 0; y < test.height; ++y)
      for (int x = 0; x < test.width; ++x) {
        const size_t i = static_cast<size_t>(y) * test.width + x, t = static_cast<size_t>(y / side) * tilesX + x / side;
        diff[t] += static_cast<double>(luminanceAt(test, i)) - luminanceAt(reference, i);
        var[t] += static_cast<double>(test.varianceY[i]) + reference.varianceY[i];
      }
    for (size_t t = 0; t < s.tiles; ++t) {
      const double z = var[t] > 0 ? std::abs(diff[t]) / std::sqrt(var[t])
                                  : (diff[t] != 0 ? std::numeric_limits<double>::infinity() : 0.0);
      s.maxAbsZ = std::max(s.maxAbsZ, std::isfinite(z) ? z : 1e30);
      if (!(z <= s.zThreshold)) ++s.failedTiles;
    }
    if (s.failedTiles > 0) r.pass = false;
    r.scales.push_back(s);
  }
  return r;
}

}  // namespace pa::regress
