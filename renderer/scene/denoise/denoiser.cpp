#include "renderer/scene/denoise/denoiser.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace pa::denoise {
namespace {

/// Albedo below this (per channel) is raised to it for demodulation; a pixel whose every
/// channel is below it is black and passes through.
constexpr float kMinAlbedo = 1e-3f;
/// Below this many samples per pixel the film's per-pixel variance is too noisy (or zero).
constexpr uint64_t kMinSamplesForPixelVariance = 4;
/// Radius of the neighbourhood of the spatial variance estimate (7 x 7, as SVGF).
constexpr int kVarianceRadius = 3;
/// Depth slack relative to the pixel's depth (covers a gradient's curvature at large steps).
constexpr float kDepthRelativeSlack = 0.005f;
/// Keeps the luminance weight finite where the noise estimate is zero.
constexpr float kLuminanceEpsilon = 1e-6f;
/// Exponents below this give weights under 1e-35: treated as zero.
constexpr float kMinExponent = -80.0f;
/// B3-spline taps of the à-trous kernel (Dammertz et al. 2010).
constexpr float kKernel[5] = {1.0f / 16.0f, 1.0f / 4.0f, 3.0f / 8.0f, 1.0f / 4.0f, 1.0f / 16.0f};
/// Taps of the 3 x 3 blur of the variance the luminance weight uses.
constexpr float kBlur[3] = {0.25f, 0.5f, 0.25f};
/// Rows per parallel task.
constexpr uint32_t kRowGrain = 4;

float luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// e^x for x <= 0: 2^(x log2 e) from an exponent-bit shift and a degree-5 polynomial of the
/// fraction (relative error < 2e-7); 0 below kMinExponent. Cheaper than std::exp and exact
/// enough for weights.
float negativeExp(float x) {
  if (!(x > kMinExponent)) return 0.0f;
  const float t = x * 1.44269504f;
  const float whole = std::floor(t);
  const float f = t - whole;   // [0, 1)
  const float p =
      1.0f + f * (0.69314718f + f * (0.24022652f + f * (0.05550411f + f * (0.00961813f + f * 0.00133336f))));
  const int32_t bits = std::bit_cast<int32_t>(p) + (static_cast<int32_t>(whole) << 23);
  return std::bit_cast<float>(bits);
}

/// Exponent of the normal weight: sigma * (dot - 1), i.e. e^(sigma (cos - 1)) ~ cos^sigma
/// near cos = 1 and ~0 for perpendicular or opposite normals.
float normalExponent(const glm::vec3& a, const glm::vec3& b, float sigma) {
  return sigma * (glm::dot(a, b) - 1.0f);
}

/// Exponent of the depth weight: how far q's depth is from what p's gradient predicts.
float depthExponent(const Denoiser::PixelGuide& p, float depthQ, float offsetX, float offsetY, float sigma) {
  const float predicted = std::abs(p.depthDx * offsetX) + std::abs(p.depthDy * offsetY);
  return -std::abs(p.depth - depthQ) / (sigma * predicted + kDepthRelativeSlack * p.depth);
}

/// Depth change per pixel between `here` and the neighbour on the side with the smaller change
/// (the side on the same surface at an edge); 0 with no usable neighbour.
float oneSidedSlope(float here, float before, float after) {
  const bool hasBefore = std::isfinite(before) && before > 0.0f;
  const bool hasAfter = std::isfinite(after) && after > 0.0f;
  const float slopeBefore = here - before;
  const float slopeAfter = after - here;
  if (hasBefore && hasAfter) return std::abs(slopeBefore) < std::abs(slopeAfter) ? slopeBefore : slopeAfter;
  if (hasBefore) return slopeBefore;
  if (hasAfter) return slopeAfter;
  return 0.0f;
}

glm::vec3 demodulationFactor(const glm::vec3& albedo) { return glm::max(albedo, glm::vec3(kMinAlbedo)); }

template <typename Body>
void parallelRows(uint32_t height, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, height, kRowGrain),
                    [&](const tbb::blocked_range<uint32_t>& r) { body(r.begin(), r.end()); });
}

}  // namespace

Denoiser::Denoiser(const Config& config) : config_(config) {
  config_.iterations = std::min(config_.iterations, 12u);
  const auto sane = [](float v, float fallback) { return std::isfinite(v) && v > 0.0f ? v : fallback; };
  const Config defaults;
  config_.sigmaNormal = sane(config_.sigmaNormal, defaults.sigmaNormal);
  config_.sigmaDepth = sane(config_.sigmaDepth, defaults.sigmaDepth);
  config_.sigmaLuminance = sane(config_.sigmaLuminance, defaults.sigmaLuminance);
}

void Denoiser::apply(const Guides& guides, std::span<glm::vec3> radiance) {
  const size_t n = size_t{guides.width} * guides.height;
  const auto check = [n](size_t size, const char* name) {
    if (size != n) {
      throw std::invalid_argument(std::string("denoise: ") + name + " has " + std::to_string(size) +
                                  " pixels, expected " + std::to_string(n));
    }
  };
  check(radiance.size(), "radiance");
  check(guides.albedo.size(), "albedo");
  check(guides.normal.size(), "normal");
  check(guides.depth.size(), "depth");
  check(guides.variance.size(), "variance");
  if (n == 0 || config_.iterations == 0) return;

  guide_.resize(n);
  current_.resize(n);
  next_.resize(n);
  const uint32_t width = guides.width;
  const uint32_t height = guides.height;

  parallelRows(height, [&](uint32_t y0, uint32_t y1) { prepareRows(guides, radiance, y0, y1); });
  if (guides.samplesPerPixel < kMinSamplesForPixelVariance) {
    parallelRows(height, [&](uint32_t y0, uint32_t y1) { estimateVarianceRows(width, height, y0, y1); });
    current_.swap(next_);
  }
  for (uint32_t i = 0; i < config_.iterations; ++i) {
    parallelRows(height, [&](uint32_t y0, uint32_t y1) { filterRows(width, height, 1u << i, y0, y1); });
    current_.swap(next_);
  }
  parallelRows(height, [&](uint32_t y0, uint32_t y1) {
    for (size_t i = size_t{y0} * width; i < size_t{y1} * width; ++i) {
      if (guide_[i].role == Role::PassThrough) {
        if (!finite(radiance[i])) radiance[i] = glm::vec3(0.0f);
      } else {
        radiance[i] = glm::vec3(current_[i]) * demodulationFactor(guides.albedo[i]);
      }
    }
  });
}

void Denoiser::prepareRows(const Guides& guides, std::span<const glm::vec3> radiance, uint32_t y0, uint32_t y1) {
  const uint32_t width = guides.width;
  const bool pixelVariance = guides.samplesPerPixel >= kMinSamplesForPixelVariance;
  const auto depthAt = [&](uint32_t x, uint32_t y) { return guides.depth[size_t{y} * width + x]; };
  const float none = std::numeric_limits<float>::infinity();
  for (uint32_t y = y0; y < y1; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = size_t{y} * width + x;
      PixelGuide& g = guide_[i];
      g = PixelGuide{};
      current_[i] = glm::vec4(0.0f);
      const float depth = guides.depth[i];
      const glm::vec3 albedo = guides.albedo[i];
      const glm::vec3 normal = guides.normal[i];
      const float normalLength = finite(normal) ? glm::length(normal) : 0.0f;
      const bool geometry = std::isfinite(depth) && depth > 0.0f && finite(albedo) && normalLength > 1e-6f &&
                            std::max({albedo.x, albedo.y, albedo.z}) >= kMinAlbedo;
      if (!geometry) continue;
      g.normal = normal / normalLength;
      g.depth = depth;
      g.depthDx = oneSidedSlope(depth, x > 0 ? depthAt(x - 1, y) : none,
                                x + 1 < width ? depthAt(x + 1, y) : none);
      g.depthDy = oneSidedSlope(depth, y > 0 ? depthAt(x, y - 1) : none,
                                y + 1 < guides.height ? depthAt(x, y + 1) : none);
      if (!finite(radiance[i])) {
        g.role = Role::Hole;
        continue;
      }
      g.role = Role::Filtered;
      const glm::vec3 factor = demodulationFactor(albedo);
      const glm::vec3 demodulated = radiance[i] / factor;
      float variance = 0.0f;
      if (pixelVariance) {
        const float scale = luminance(factor);
        const float v = guides.variance[i] / (scale * scale);
        variance = std::isfinite(v) && v > 0.0f ? v : 0.0f;
      }
      current_[i] = glm::vec4(demodulated, variance);
    }
  }
}

void Denoiser::estimateVarianceRows(uint32_t width, uint32_t height, uint32_t y0, uint32_t y1) {
  for (uint32_t y = y0; y < y1; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = size_t{y} * width + x;
      next_[i] = current_[i];
      const PixelGuide& p = guide_[i];
      if (p.role != Role::Filtered) continue;
      double weightSum = 0.0, sum = 0.0, sumSquares = 0.0;
      const int yLow = std::max(0, static_cast<int>(y) - kVarianceRadius);
      const int yHigh = std::min(static_cast<int>(height) - 1, static_cast<int>(y) + kVarianceRadius);
      const int xLow = std::max(0, static_cast<int>(x) - kVarianceRadius);
      const int xHigh = std::min(static_cast<int>(width) - 1, static_cast<int>(x) + kVarianceRadius);
      for (int qy = yLow; qy <= yHigh; ++qy) {
        for (int qx = xLow; qx <= xHigh; ++qx) {
          const size_t j = static_cast<size_t>(qy) * width + static_cast<size_t>(qx);
          const PixelGuide& q = guide_[j];
          if (q.role != Role::Filtered) continue;
          const float exponent = normalExponent(p.normal, q.normal, config_.sigmaNormal) +
                                 depthExponent(p, q.depth, static_cast<float>(qx - static_cast<int>(x)),
                                               static_cast<float>(qy - static_cast<int>(y)), config_.sigmaDepth);
          const float w = j == i ? 1.0f : negativeExp(exponent);
          const float l = luminance(glm::vec3(current_[j]));
          weightSum += w;
          sum += w * l;
          sumSquares += w * l * l;
        }
      }
      const double mean = sum / weightSum;
      next_[i].w = static_cast<float>(std::max(0.0, sumSquares / weightSum - mean * mean));
    }
  }
}

void Denoiser::filterRows(uint32_t width, uint32_t height, uint32_t step, uint32_t y0, uint32_t y1) {
  const int w = static_cast<int>(width);
  const int h = static_cast<int>(height);
  const int s = static_cast<int>(step);
  for (uint32_t y = y0; y < y1; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = size_t{y} * width + x;
      const PixelGuide& p = guide_[i];
      if (p.role == Role::PassThrough) {
        next_[i] = current_[i];
        continue;
      }
      const int px = static_cast<int>(x);
      const int py = static_cast<int>(y);
      // Noise of p: 3 x 3 blur of the variance over filtered pixels.
      float blurWeight = 0.0f, blurredVariance = 0.0f;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = px + dx, qy = py + dy;
          if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          const size_t j = static_cast<size_t>(qy) * width + static_cast<size_t>(qx);
          if (guide_[j].role != Role::Filtered) continue;
          const float k = kBlur[dx + 1] * kBlur[dy + 1];
          blurWeight += k;
          blurredVariance += k * current_[j].w;
        }
      }
      const float sigmaL = blurWeight > 0.0f ? config_.sigmaLuminance * std::sqrt(blurredVariance / blurWeight) : 0.0f;
      // A hole has no luminance of its own yet: only geometry decides.
      const float inverseLuminanceTolerance = p.role == Role::Hole ? 0.0f : 1.0f / (sigmaL + kLuminanceEpsilon);
      const float luminanceP = luminance(glm::vec3(current_[i]));

      glm::vec3 color(0.0f);
      float weightSum = 0.0f, varianceSum = 0.0f;
      for (int ky = 0; ky < 5; ++ky) {
        const int qy = py + (ky - 2) * s;
        if (qy < 0 || qy >= h) continue;
        for (int kx = 0; kx < 5; ++kx) {
          const int qx = px + (kx - 2) * s;
          if (qx < 0 || qx >= w) continue;
          const size_t j = static_cast<size_t>(qy) * width + static_cast<size_t>(qx);
          const PixelGuide& q = guide_[j];
          if (q.role != Role::Filtered) continue;   // a hole's own centre is skipped here too
          const glm::vec4 c = current_[j];
          float weight = kKernel[kx] * kKernel[ky];
          if (j != i) {
            const float exponent =
                normalExponent(p.normal, q.normal, config_.sigmaNormal) +
                depthExponent(p, q.depth, static_cast<float>(qx - px), static_cast<float>(qy - py),
                              config_.sigmaDepth) -
                std::abs(luminanceP - luminance(glm::vec3(c))) * inverseLuminanceTolerance;
            weight *= negativeExp(exponent);
          }
          color += weight * glm::vec3(c);
          weightSum += weight;
          varianceSum += weight * weight * c.w;
        }
      }
      next_[i] = weightSum > 0.0f ? glm::vec4(color / weightSum, varianceSum / (weightSum * weightSum))
                                  : glm::vec4(0.0f);
    }
  }
}

}  // namespace pa::denoise
