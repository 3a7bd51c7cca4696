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
/// Radius of the neighbourhood of the spatial variance estimate (5 x 5).
constexpr int kVarianceRadius = 2;
/// Most à-trous passes (the last step is 2^(n-1) pixels; the border is that wide).
constexpr uint32_t kMaxIterations = 10;
/// Depth slack relative to the pixel's depth (covers a gradient's curvature at large steps).
constexpr float kDepthRelativeSlack = 0.005f;
/// Keeps the luminance weight finite where the noise estimate is zero.
constexpr float kLuminanceEpsilon = 1e-6f;
/// Weight exponents are clamped here (e^-80 ~ 2e-35: nothing); NaN exponents land here too.
constexpr float kMinExponent = -80.0f;
/// Taps of the 3 x 3 à-trous kernel (B-spline (1, 2, 1) / 4) and of the variance blur.
constexpr float kKernel[3] = {0.25f, 0.5f, 0.25f};
/// Rows per parallel task.
constexpr uint32_t kRowGrain = 4;

float luminance(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// e^x for x <= 0 without branches (so that loops over it vectorise): 2^(x log2 e) from an
/// exponent-bit shift and a degree-5 polynomial of the fraction (relative error < 2e-7).
/// Exponents below kMinExponent, and NaN, count as kMinExponent.
inline float negativeExp(float x) {
  x = x > kMinExponent ? x : kMinExponent;
  x = x < 0.0f ? x : 0.0f;
  const float t = x * 1.44269504f;
  const float whole = std::floor(t);
  const float f = t - whole;   // [0, 1)
  const float p =
      1.0f + f * (0.69314718f + f * (0.24022652f + f * (0.05550411f + f * (0.00961813f + f * 0.00133336f))));
  return std::bit_cast<float>(std::bit_cast<int32_t>(p) + (static_cast<int32_t>(whole) << 23));
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

/// The unfiltered part of pixel i's radiance (0 without an emission guide or where it is not finite).
glm::vec3 emissionAt(const Guides& guides, size_t i) {
  if (guides.emission.empty() || !finite(guides.emission[i])) return glm::vec3(0.0f);
  return guides.emission[i];
}

template <typename Body>
void parallelRows(uint32_t height, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, height, kRowGrain),
                    [&](const tbb::blocked_range<uint32_t>& r) { body(r.begin(), r.end()); });
}

}  // namespace

Denoiser::Denoiser(const Config& config) : config_(config) {
  config_.iterations = std::min(config_.iterations, kMaxIterations);
  const auto sane = [](float v, float fallback) { return std::isfinite(v) && v > 0.0f ? v : fallback; };
  const Config defaults;
  config_.sigmaNormal = sane(config_.sigmaNormal, defaults.sigmaNormal);
  config_.sigmaDepth = sane(config_.sigmaDepth, defaults.sigmaDepth);
  config_.sigmaLuminance = sane(config_.sigmaLuminance, defaults.sigmaLuminance);
}

void Denoiser::resize(uint32_t width, uint32_t height) {
  width_ = width;
  height_ = height;
  pad_ = std::max<uint32_t>(kVarianceRadius, config_.iterations > 0 ? 1u << (config_.iterations - 1) : 0u);
  const size_t stride = width + 2 * size_t{pad_};
  const size_t size = stride * (height + 2 * size_t{pad_});
  for (Plane* plane : {&normalX_, &normalY_, &normalZ_, &depth_, &depthDx_, &depthDy_, &gives_, &takes_, &ownVariance_,
                       &current_.red, &current_.green, &current_.blue, &current_.variance, &next_.red,
                       &next_.green, &next_.blue, &next_.variance}) {
    plane->data.assign(size, 0.0f);   // the border stays zero: gives = 0 there
    plane->stride = stride;
    plane->pad = pad_;
  }
}

void Denoiser::apply(const Guides& guides, std::span<glm::vec3> radiance) { apply(guides, radiance, {}); }

void Denoiser::apply(const Guides& guides, std::span<glm::vec3> radiance, std::span<glm::vec3> firstPass) {
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
  if (!guides.emission.empty()) check(guides.emission.size(), "emission");
  if (!guides.historyLength.empty()) check(guides.historyLength.size(), "historyLength");
  if (!firstPass.empty()) check(firstPass.size(), "firstPass");
  if (n == 0 || config_.iterations == 0) return;

  if (guides.width != width_ || guides.height != height_ || gives_.data.empty()) resize(guides.width, guides.height);
  const uint32_t height = guides.height;
  parallelRows(height, [&](uint32_t y0, uint32_t y1) { prepareRows(guides, radiance, y0, y1); });
  if (!guides.historyLength.empty() || guides.samplesPerPixel < kMinSamplesForPixelVariance) {
    parallelRows(height, [&](uint32_t y0, uint32_t y1) { estimateVarianceRows(y0, y1); });
    std::swap(current_, next_);
  }
  for (uint32_t i = 0; i < config_.iterations; ++i) {
    parallelRows(height, [&](uint32_t y0, uint32_t y1) { filterRows(1u << i, y0, y1); });
    std::swap(current_, next_);
    if (i == 0 && !firstPass.empty()) {
      parallelRows(height, [&](uint32_t y0, uint32_t y1) {
        for (uint32_t y = y0; y < y1; ++y) {
          const int row = static_cast<int>(y);
          const float* takes = takes_.row(row);
          const float *r = current_.red.row(row), *g = current_.green.row(row), *b = current_.blue.row(row);
          for (uint32_t x = 0; x < guides.width; ++x)
            if (takes[x] > 0.0f) firstPass[size_t{y} * guides.width + x] = glm::vec3(r[x], g[x], b[x]);
        }
      });
    }
  }
  parallelRows(height, [&](uint32_t y0, uint32_t y1) {
    for (uint32_t y = y0; y < y1; ++y) {
      const int row = static_cast<int>(y);
      const float* takes = takes_.row(row);
      const float *r = current_.red.row(row), *g = current_.green.row(row), *b = current_.blue.row(row);
      for (uint32_t x = 0; x < guides.width; ++x) {
        const size_t i = size_t{y} * guides.width + x;
        if (takes[x] > 0.0f) {
          radiance[i] = glm::vec3(r[x], g[x], b[x]) * demodulationFactor(guides.albedo[i]) + emissionAt(guides, i);
        } else if (!finite(radiance[i])) {
          radiance[i] = glm::vec3(0.0f);
        }
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
    const int row = static_cast<int>(y);
    float *nx = normalX_.row(row), *ny = normalY_.row(row), *nz = normalZ_.row(row);
    float *depth = depth_.row(row), *dx = depthDx_.row(row), *dy = depthDy_.row(row);
    float *gives = gives_.row(row), *takes = takes_.row(row), *own = ownVariance_.row(row);
    float *r = current_.red.row(row), *g = current_.green.row(row), *b = current_.blue.row(row);
    float* variance = current_.variance.row(row);
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = size_t{y} * width + x;
      nx[x] = ny[x] = nz[x] = depth[x] = dx[x] = dy[x] = gives[x] = takes[x] = own[x] = 0.0f;
      r[x] = g[x] = b[x] = variance[x] = 0.0f;
      const float z = guides.depth[i];
      const glm::vec3 albedo = guides.albedo[i];
      const glm::vec3 normal = guides.normal[i];
      const float normalLength = finite(normal) ? glm::length(normal) : 0.0f;
      const bool geometry = std::isfinite(z) && z > 0.0f && finite(albedo) && normalLength > 1e-6f &&
                            std::max({albedo.x, albedo.y, albedo.z}) >= kMinAlbedo;
      if (!geometry) continue;   // sky, black albedo or broken guides: passes through
      nx[x] = normal.x / normalLength;
      ny[x] = normal.y / normalLength;
      nz[x] = normal.z / normalLength;
      depth[x] = z;
      dx[x] = oneSidedSlope(z, x > 0 ? depthAt(x - 1, y) : none, x + 1 < width ? depthAt(x + 1, y) : none);
      dy[x] = oneSidedSlope(z, y > 0 ? depthAt(x, y - 1) : none, y + 1 < guides.height ? depthAt(x, y + 1) : none);
      takes[x] = 1.0f;
      if (!finite(radiance[i])) continue;   // a hole: filled from its neighbours, never used by them
      gives[x] = 1.0f;
      const glm::vec3 factor = demodulationFactor(albedo);
      const glm::vec3 demodulated = (radiance[i] - emissionAt(guides, i)) / factor;
      r[x] = demodulated.r;
      g[x] = demodulated.g;
      b[x] = demodulated.b;
      const bool ownVariance = guides.historyLength.empty() ? pixelVariance : guides.historyLength[i] >= 4.0f;
      if (ownVariance) {
        own[x] = 1.0f;
        const float scale = luminance(factor.r, factor.g, factor.b);
        const float v = guides.variance[i] / (scale * scale);
        variance[x] = std::isfinite(v) && v > 0.0f ? v : 0.0f;
      }
    }
  }
}

namespace {

/// One neighbour offset's rows: the guides and signal at (x + dx, y + dy) for x = 0, 1, ...
struct Tap {
  const float* nx;
  const float* ny;
  const float* nz;
  const float* depth;
  const float* gives;
  const float* red;
  const float* green;
  const float* blue;
  const float* variance;
  float offsetX, offsetY;   // (dx, dy) in pixels
  float kernel;             // spatial weight of the tap
};

/// The centre pixels' row of guides and what the taps' weights need from it.
struct Centre {
  const float* nx;
  const float* ny;
  const float* nz;
  const float* depth;
  const float* depthDx;
  const float* depthDy;
  const float* luminance;           // demodulated luminance
  const float* inverseTolerance;    // 1 / luminance tolerance; 0 = no luminance weight
};

/// Running sums of one row's weighted taps.
struct Sums {
  float* red;
  float* green;
  float* blue;
  float* weight;
  float* variance;   // weighted sum of variance (w^2) or of luminance^2 (moments)
};

/// Edge-stopping weight of tap t at pixel x of a row: normal, depth and (where the centre's
/// inverseTolerance > 0) luminance; luminanceQ is the tap's luminance.
inline float tapWeight(const Centre& c, const Tap& t, int x, float luminanceQ, float sigmaNormal, float sigmaDepth) {
  const float dot = c.nx[x] * t.nx[x] + c.ny[x] * t.ny[x] + c.nz[x] * t.nz[x];
  const float expected = std::abs(c.depthDx[x] * t.offsetX) + std::abs(c.depthDy[x] * t.offsetY);
  const float exponent = sigmaNormal * (dot - 1.0f) -
                         std::abs(c.depth[x] - t.depth[x]) / (sigmaDepth * expected + kDepthRelativeSlack * c.depth[x]) -
                         std::abs(c.luminance[x] - luminanceQ) * c.inverseTolerance[x];
  return t.kernel * t.gives[x] * negativeExp(exponent);
}

// The two loops below carry no dependence between pixels (each x reads and writes only entry
// x of the sums, which never overlap the inputs): ivdep lets them vectorise.

/// Adds one tap of the à-trous filter to a row's sums (colour, weight, w^2 variance).
void addFilterTap(const Centre& c, const Tap& t, const Sums& sums, int width, float sigmaNormal, float sigmaDepth) {
#pragma GCC ivdep
  for (int x = 0; x < width; ++x) {
    const float w = tapWeight(c, t, x, luminance(t.red[x], t.green[x], t.blue[x]), sigmaNormal, sigmaDepth);
    sums.red[x] += w * t.red[x];
    sums.green[x] += w * t.green[x];
    sums.blue[x] += w * t.blue[x];
    sums.weight[x] += w;
    sums.variance[x] += w * w * t.variance[x];
  }
}

/// Adds one tap of the spatial variance estimate: moments of luminance (red = sum of l,
/// variance = sum of l^2) with geometric weights only.
void addMomentTap(const Centre& c, const Tap& t, const Sums& sums, int width, float sigmaNormal, float sigmaDepth) {
#pragma GCC ivdep
  for (int x = 0; x < width; ++x) {
    const float l = luminance(t.red[x], t.green[x], t.blue[x]);
    const float w = tapWeight(c, t, x, l, sigmaNormal, sigmaDepth);
    sums.red[x] += w * l;
    sums.weight[x] += w;
    sums.variance[x] += w * l * l;
  }
}

}  // namespace

Denoiser::RowScratch& Denoiser::RowScratch::sized(uint32_t width) {
  for (std::vector<float>* v : {&red, &green, &blue, &weight, &variance, &luminance, &inverseTolerance})
    v->assign(width, 0.0f);
  return *this;
}

template <typename Body>
void Denoiser::forEachRow(uint32_t y0, uint32_t y1, Body&& body) {
  const int width = static_cast<int>(width_);
  RowScratch& scratch = rowScratch_.local();
  for (uint32_t y = y0; y < y1; ++y) {
    const int row = static_cast<int>(y);
    scratch.sized(width_);
    const float *r = current_.red.row(row), *g = current_.green.row(row), *b = current_.blue.row(row);
    for (int x = 0; x < width; ++x) scratch.luminance[x] = luminance(r[x], g[x], b[x]);
    const Centre centre{normalX_.row(row), normalY_.row(row),          normalZ_.row(row),
                        depth_.row(row),   depthDx_.row(row),          depthDy_.row(row),
                        scratch.luminance.data(), scratch.inverseTolerance.data()};
    const Sums sums{scratch.red.data(), scratch.green.data(), scratch.blue.data(), scratch.weight.data(),
                    scratch.variance.data()};
    const auto tapAt = [this, row](int dx, int dy, float kernel) {
      const int q = row + dy;
      return Tap{normalX_.row(q) + dx,     normalY_.row(q) + dx,       normalZ_.row(q) + dx,
                 depth_.row(q) + dx,       gives_.row(q) + dx,         current_.red.row(q) + dx,
                 current_.green.row(q) + dx, current_.blue.row(q) + dx, current_.variance.row(q) + dx,
                 static_cast<float>(dx),   static_cast<float>(dy),     kernel};
    };
    body(row, centre, sums, tapAt, scratch);
  }
}

void Denoiser::estimateVarianceRows(uint32_t y0, uint32_t y1) {
  const int width = static_cast<int>(width_);
  forEachRow(y0, y1, [&](int row, const Centre& centre, const Sums& sums, const auto& tapAt, RowScratch&) {
    // The centre's inverseTolerance stays 0 (as sized): geometric weights only.
    for (int dy = -kVarianceRadius; dy <= kVarianceRadius; ++dy)
      for (int dx = -kVarianceRadius; dx <= kVarianceRadius; ++dx)
        addMomentTap(centre, tapAt(dx, dy, 1.0f), sums, width, config_.sigmaNormal, config_.sigmaDepth);
    const float* gives = gives_.row(row);
    const float* own = ownVariance_.row(row);
    const float* given = current_.variance.row(row);
    float* out = next_.variance.row(row);
    for (int x = 0; x < width; ++x) {
      const float inverse = 1.0f / std::max(sums.weight[x], 1e-30f);
      const float mean = sums.red[x] * inverse;
      const float variance = sums.variance[x] * inverse - mean * mean;
      const float estimated = (gives[x] > 0.0f) & (variance > 0.0f) ? variance : 0.0f;
      out[x] = own[x] > 0.0f ? given[x] : estimated;
    }
    std::copy_n(current_.red.row(row), width, next_.red.row(row));
    std::copy_n(current_.green.row(row), width, next_.green.row(row));
    std::copy_n(current_.blue.row(row), width, next_.blue.row(row));
  });
}

void Denoiser::filterRows(uint32_t step, uint32_t y0, uint32_t y1) {
  const int width = static_cast<int>(width_);
  const int s = static_cast<int>(step);
  forEachRow(y0, y1, [&](int row, const Centre& centre, const Sums& sums, const auto& tapAt, RowScratch& scratch) {
    // Noise of each pixel: 3 x 3 blur of the variance over valid pixels, as a luminance tolerance.
    {
      float* blurWeight = scratch.weight.data();
      float* blurred = scratch.variance.data();
      for (int dy = -1; dy <= 1; ++dy) {
        const float* gives = gives_.row(row + dy);
        const float* variance = current_.variance.row(row + dy);
        for (int dx = -1; dx <= 1; ++dx) {
          const float k = kKernel[dx + 1] * kKernel[dy + 1];
          for (int x = 0; x < width; ++x) {
            blurWeight[x] += k * gives[x + dx];
            blurred[x] += k * gives[x + dx] * variance[x + dx];
          }
        }
      }
      const float* gives = gives_.row(row);
      float* inverseTolerance = scratch.inverseTolerance.data();
      for (int x = 0; x < width; ++x) {
        const float sigma =
            config_.sigmaLuminance * std::sqrt(std::max(blurred[x], 0.0f) / std::max(blurWeight[x], 1e-30f));
        // A hole (gives = 0) has no luminance of its own yet: only geometry decides.
        inverseTolerance[x] = gives[x] / (sigma + kLuminanceEpsilon);
        blurWeight[x] = 0.0f;
        blurred[x] = 0.0f;
      }
    }
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        addFilterTap(centre, tapAt(dx * s, dy * s, kKernel[dx + 1] * kKernel[dy + 1]), sums, width,
                     config_.sigmaNormal, config_.sigmaDepth);
    const float* takes = takes_.row(row);
    float* outRed = next_.red.row(row);
    float* outGreen = next_.green.row(row);
    float* outBlue = next_.blue.row(row);
    float* outVariance = next_.variance.row(row);
    for (int x = 0; x < width; ++x) {
      const bool filtered = (takes[x] > 0.0f) & (sums.weight[x] > 0.0f);
      const float inverse = 1.0f / std::max(sums.weight[x], 1e-30f);
      outRed[x] = filtered ? sums.red[x] * inverse : 0.0f;
      outGreen[x] = filtered ? sums.green[x] * inverse : 0.0f;
      outBlue[x] = filtered ? sums.blue[x] * inverse : 0.0f;
      outVariance[x] = filtered ? sums.variance[x] * inverse * inverse : 0.0f;
    }
  });
}

}  // namespace pa::denoise
