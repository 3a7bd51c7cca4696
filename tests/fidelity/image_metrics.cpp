#include "tests/fidelity/image_metrics.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pa::fidelity {
namespace {

constexpr int kWindow = 11;        // Gaussian window side (Wang et al. 2004)
constexpr double kSigma = 1.5;     // Gaussian standard deviation in pixels
constexpr double kRange = 255.0;   // dynamic range L of 8-bit samples
constexpr double kC1 = (0.01 * kRange) * (0.01 * kRange);
constexpr double kC2 = (0.03 * kRange) * (0.03 * kRange);

std::array<double, kWindow> gaussianWeights() {
  std::array<double, kWindow> weights{};
  double sum = 0;
  for (int i = 0; i < kWindow; ++i) {
    const double offset = i - kWindow / 2;
    weights[i] = std::exp(-(offset * offset) / (2 * kSigma * kSigma));
    sum += weights[i];
  }
  for (double& w : weights) w /= sum;
  return weights;
}

// Separable 'valid' filtering: output is (width - 10) x (height - 10).
std::vector<double> filterValid(const std::vector<double>& plane, int width, int height,
                                const std::array<double, kWindow>& weights) {
  const int outWidth = width - kWindow + 1;
  const int outHeight = height - kWindow + 1;
  std::vector<double> rows(static_cast<size_t>(outWidth) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < outWidth; ++x) {
      double sum = 0;
      for (int k = 0; k < kWindow; ++k) sum += weights[k] * plane[static_cast<size_t>(y) * width + x + k];
      rows[static_cast<size_t>(y) * outWidth + x] = sum;
    }
  std::vector<double> out(static_cast<size_t>(outWidth) * outHeight);
  for (int y = 0; y < outHeight; ++y)
    for (int x = 0; x < outWidth; ++x) {
      double sum = 0;
      for (int k = 0; k < kWindow; ++k) sum += weights[k] * rows[static_cast<size_t>(y + k) * outWidth + x];
      out[static_cast<size_t>(y) * outWidth + x] = sum;
    }
  return out;
}

}  // namespace

RgbImage loadRgb(const std::string& path) {
  int width = 0, height = 0, channels = 0;
  stbi_uc* data = stbi_load(path.c_str(), &width, &height, &channels, 3);
  if (data == nullptr)
    throw std::runtime_error(path + ": cannot decode image: " + stbi_failure_reason());
  RgbImage image{width, height, {}};
  image.pixels.assign(data, data + static_cast<size_t>(width) * height * 3);
  stbi_image_free(data);
  return image;
}

void savePng(const std::string& path, const RgbImage& image) {
  if (stbi_write_png(path.c_str(), image.width, image.height, 3, image.pixels.data(), image.width * 3) == 0)
    throw std::runtime_error(path + ": cannot write PNG");
}

double meanLinearLuminance(const RgbImage& image) {
  std::array<double, 256> decoded{};
  for (int i = 0; i < 256; ++i) {
    const double c = i / 255.0;
    decoded[i] = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  }
  const size_t pixels = static_cast<size_t>(image.width) * image.height;
  if (pixels == 0) return 0.0;
  double sum = 0.0;
  for (size_t i = 0; i < pixels; ++i) {
    const std::uint8_t* p = &image.pixels[3 * i];
    sum += 0.2126 * decoded[p[0]] + 0.7152 * decoded[p[1]] + 0.0722 * decoded[p[2]];
  }
  return sum / static_cast<double>(pixels);
}

std::vector<double> luma(const RgbImage& image) {
  std::vector<double> y(static_cast<size_t>(image.width) * image.height);
  for (size_t i = 0; i < y.size(); ++i) {
    const std::uint8_t* p = &image.pixels[i * 3];
    y[i] = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
  }
  return y;
}

double ssimLuma(std::span<const double> a, std::span<const double> b, int width, int height) {
  if (width < kWindow || height < kWindow)
    throw std::invalid_argument("ssim: images must be at least 11x11 pixels");
  const size_t count = static_cast<size_t>(width) * height;
  if (a.size() != count || b.size() != count) throw std::invalid_argument("ssim: plane sizes differ");
  const auto weights = gaussianWeights();
  std::vector<double> aa(count), bb(count), ab(count);
  for (size_t i = 0; i < count; ++i) {
    aa[i] = a[i] * a[i];
    bb[i] = b[i] * b[i];
    ab[i] = a[i] * b[i];
  }
  const std::vector<double> planeA(a.begin(), a.end()), planeB(b.begin(), b.end());
  const auto muA = filterValid(planeA, width, height, weights);
  const auto muB = filterValid(planeB, width, height, weights);
  const auto meanAA = filterValid(aa, width, height, weights);
  const auto meanBB = filterValid(bb, width, height, weights);
  const auto meanAB = filterValid(ab, width, height, weights);
  double sum = 0;
  for (size_t i = 0; i < muA.size(); ++i) {
    const double varA = meanAA[i] - muA[i] * muA[i];
    const double varB = meanBB[i] - muB[i] * muB[i];
    const double covariance = meanAB[i] - muA[i] * muB[i];
    sum += ((2 * muA[i] * muB[i] + kC1) * (2 * covariance + kC2)) /
           ((muA[i] * muA[i] + muB[i] * muB[i] + kC1) * (varA + varB + kC2));
  }
  return sum / static_cast<double>(muA.size());
}

Comparison compare(const RgbImage& a, const RgbImage& b) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("compare: sizes differ (" + std::to_string(a.width) + "x" +
                                std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" +
                                std::to_string(b.height) + ")");
  Comparison result;
  double squared = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const double d = static_cast<double>(a.pixels[i]) - b.pixels[i];
    squared += d * d;
    result.maxAbsDiff = std::max(result.maxAbsDiff, std::abs(d));
  }
  result.mse = a.pixels.empty() ? 0 : squared / static_cast<double>(a.pixels.size());
  result.psnr = result.mse == 0 ? std::numeric_limits<double>::infinity()
                                : 10 * std::log10(kRange * kRange / result.mse);
  result.ssim = ssimLuma(luma(a), luma(b), a.width, a.height);
  return result;
}

WorstTile worstTile(const RgbImage& a, const RgbImage& b, int size) {
  if (a.width != b.width || a.height != b.height) throw std::invalid_argument("worstTile: sizes differ");
  if (size < 1) throw std::invalid_argument("worstTile: tile size must be positive");
  WorstTile worst{0, 0, size, -1, 0};
  for (int ty = 0; ty < a.height; ty += size)
    for (int tx = 0; tx < a.width; tx += size) {
      const int endX = std::min(a.width, tx + size), endY = std::min(a.height, ty + size);
      double squared = 0;
      for (int y = ty; y < endY; ++y)
        for (int i = (y * a.width + tx) * 3; i < (y * a.width + endX) * 3; ++i) {
          const double d = static_cast<double>(a.pixels[i]) - b.pixels[i];
          squared += d * d;
        }
      const double mse = squared / (3.0 * (endX - tx) * (endY - ty));
      if (mse > worst.mse) worst = WorstTile{tx, ty, size, mse, 0};
    }
  worst.mse = std::max(worst.mse, 0.0);
  worst.psnr = worst.mse == 0 ? std::numeric_limits<double>::infinity() : 10 * std::log10(kRange * kRange / worst.mse);
  return worst;
}

RgbImage differenceImage(const RgbImage& a, const RgbImage& b, double gain) {
  if (a.width != b.width || a.height != b.height) throw std::invalid_argument("difference: sizes differ");
  RgbImage out{a.width, a.height, std::vector<std::uint8_t>(a.pixels.size())};
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const double d = std::abs(static_cast<double>(a.pixels[i]) - b.pixels[i]) * gain;
    out.pixels[i] = static_cast<std::uint8_t>(std::min(255.0, d));
  }
  return out;
}

RgbImage crop(const RgbImage& image, int x, int y, int width, int height) {
  if (width <= 0 || height <= 0 || x < 0 || y < 0 || x + width > image.width || y + height > image.height)
    throw std::invalid_argument("crop rectangle outside the image");
  RgbImage out{width, height, std::vector<std::uint8_t>(static_cast<size_t>(width) * height * 3)};
  for (int row = 0; row < height; ++row) {
    const auto from = image.pixels.begin() + (static_cast<std::ptrdiff_t>(y + row) * image.width + x) * 3;
    std::copy(from, from + width * 3, out.pixels.begin() + static_cast<std::ptrdiff_t>(row) * width * 3);
  }
  return out;
}

}  // namespace pa::fidelity
