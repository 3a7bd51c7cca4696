#include "renderer/scene/denoise/denoiser.h"

#include "renderer/core/finite.h"
#include "renderer/scene/denoise/weight_lanes.h"

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
/// Taps of the 3 x 3 à-trous kernel (B-spline (1, 2, 1) / 4) and of the variance blur.
constexpr float kKernel[3] = {0.25f, 0.5f, 0.25f};
/// Rows per parallel task.
constexpr uint32_t kRowGrain = 4;

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
    // The border stays zero (gives = 0 there); kCount more floats let a row's last block of
    // lanes read past the end of the last padded row.
    plane->data.assign(size + lanes::kCount, 0.0f);
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
    std::swap(current_.variance, next_.variance);   // the colour planes stay as they are
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
    const auto pixel = [&](uint32_t x) {
      const size_t i = size_t{y} * width + x;
      nx[x] = ny[x] = nz[x] = depth[x] = dx[x] = dy[x] = gives[x] = takes[x] = own[x] = 0.0f;
      r[x] = g[x] = b[x] = variance[x] = 0.0f;
      const float z = guides.depth[i];
      const glm::vec3 albedo = guides.albedo[i];
      const glm::vec3 normal = guides.normal[i];
      const float normalLength = finite(normal) ? glm::length(normal) : 0.0f;
      const bool geometry = std::isfinite(z) && z > 0.0f && finite(albedo) && normalLength > 1e-6f &&
                            std::max({albedo.x, albedo.y, albedo.z}) >= kMinAlbedo;
      if (!geometry) return;   // sky, black albedo or broken guides: passes through
      nx[x] = normal.x / normalLength;
      ny[x] = normal.y / normalLength;
      nz[x] = normal.z / normalLength;
      depth[x] = z;
      dx[x] = oneSidedSlope(z, x > 0 ? depthAt(x - 1, y) : none, x + 1 < width ? depthAt(x + 1, y) : none);
      dy[x] = oneSidedSlope(z, y > 0 ? depthAt(x, y - 1) : none, y + 1 < guides.height ? depthAt(x, y + 1) : none);
      takes[x] = 1.0f;
      if (!finite(radiance[i])) return;   // a hole: filled from its neighbours, never used by them
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
    };
    // Interior pixels (both row neighbours inside the row) kCount at a time, the others one by one:
    // the same operations in the same order, so the same bits.
    uint32_t x = 0;
    if (width > lanes::kCount + 1) {
      pixel(0);
      for (x = 1; x + lanes::kCount < width; x += lanes::kCount) prepareLanes(guides, radiance, x, y);
    }
    for (; x < width; ++x) pixel(x);
  }
}

void Denoiser::prepareLanes(const Guides& guides, std::span<const glm::vec3> radiance, uint32_t x, uint32_t y) {
  using lanes::F;
  using lanes::I;
  const uint32_t width = guides.width;
  const size_t i = size_t{y} * width + x;
  const int row = static_cast<int>(y);
  const F zero = lanes::splat(0.0f), one = lanes::splat(1.0f), none = lanes::splat(std::numeric_limits<float>::infinity());
  const I channel = lanes::kIota * 3;
  const auto gather3 = [&](const glm::vec3* v, F& a, F& b, F& c) {
    const float* base = &v[i].x;
    a = lanes::gather(base, channel);
    b = lanes::gather(base + 1, channel);
    c = lanes::gather(base + 2, channel);
  };
  const auto allFinite = [](F a, F b, F c) { return lanes::finite(a) & lanes::finite(b) & lanes::finite(c); };
  const F z = lanes::load(guides.depth.data() + i);
  F albedoR, albedoG, albedoB, normalX, normalY, normalZ;
  gather3(guides.albedo.data(), albedoR, albedoG, albedoB);
  gather3(guides.normal.data(), normalX, normalY, normalZ);
  const I normalFinite = allFinite(normalX, normalY, normalZ);
  const F normalLength =
      lanes::select(normalFinite, lanes::sqrt(normalX * normalX + normalY * normalY + normalZ * normalZ), zero);
  const F largest = lanes::select(albedoR < albedoG, albedoG, albedoR);
  const I geometry = lanes::finite(z) & (z > 0.0f) & allFinite(albedoR, albedoG, albedoB) & (normalLength > 1e-6f) &
                     (lanes::select(largest < albedoB, albedoB, largest) >= kMinAlbedo);
  // Depth change per pixel towards the neighbour with the smaller change (oneSidedSlope).
  const auto slope = [&](F before, F after) {
    const I hasBefore = lanes::finite(before) & (before > 0.0f);
    const I hasAfter = lanes::finite(after) & (after > 0.0f);
    const F slopeBefore = z - before, slopeAfter = after - z;
    const F both = lanes::select(absolute(slopeBefore) < absolute(slopeAfter), slopeBefore, slopeAfter);
    return lanes::select(hasBefore & hasAfter, both,
                         lanes::select(hasBefore, slopeBefore, lanes::select(hasAfter, slopeAfter, zero)));
  };
  const F above = y > 0 ? lanes::load(guides.depth.data() + i - width) : none;
  const F below = y + 1 < guides.height ? lanes::load(guides.depth.data() + i + width) : none;
  F radianceR, radianceG, radianceB, emissionR = zero, emissionG = zero, emissionB = zero;
  gather3(radiance.data(), radianceR, radianceG, radianceB);
  if (!guides.emission.empty()) {
    gather3(guides.emission.data(), emissionR, emissionG, emissionB);
    const I emissionFinite = allFinite(emissionR, emissionG, emissionB);
    emissionR = lanes::select(emissionFinite, emissionR, zero);
    emissionG = lanes::select(emissionFinite, emissionG, zero);
    emissionB = lanes::select(emissionFinite, emissionB, zero);
  }
  const I gives = geometry & allFinite(radianceR, radianceG, radianceB);
  const F factorR = maxOf(albedoR, lanes::splat(kMinAlbedo)), factorG = maxOf(albedoG, lanes::splat(kMinAlbedo)),
          factorB = maxOf(albedoB, lanes::splat(kMinAlbedo));
  I own;
  if (guides.historyLength.empty()) {
    own = lanes::splat(int32_t{guides.samplesPerPixel >= kMinSamplesForPixelVariance ? -1 : 0});
  } else {
    own = lanes::load(guides.historyLength.data() + i) >= 4.0f;
  }
  own &= gives;
  const F scale = luminance(factorR, factorG, factorB);
  const F v = lanes::load(guides.variance.data() + i) / (scale * scale);
  const auto keep = [](I mask, F value) { return lanes::select(mask, value, lanes::splat(0.0f)); };
  lanes::store(normalX_.row(row) + x, keep(geometry, normalX / normalLength));
  lanes::store(normalY_.row(row) + x, keep(geometry, normalY / normalLength));
  lanes::store(normalZ_.row(row) + x, keep(geometry, normalZ / normalLength));
  lanes::store(depth_.row(row) + x, keep(geometry, z));
  lanes::store(depthDx_.row(row) + x,
               keep(geometry, slope(lanes::load(guides.depth.data() + i - 1), lanes::load(guides.depth.data() + i + 1))));
  lanes::store(depthDy_.row(row) + x, keep(geometry, slope(above, below)));
  lanes::store(takes_.row(row) + x, keep(geometry, one));
  lanes::store(gives_.row(row) + x, keep(gives, one));
  lanes::store(ownVariance_.row(row) + x, keep(own, one));
  lanes::store(current_.red.row(row) + x, keep(gives, (radianceR - emissionR) / factorR));
  lanes::store(current_.green.row(row) + x, keep(gives, (radianceG - emissionG) / factorG));
  lanes::store(current_.blue.row(row) + x, keep(gives, (radianceB - emissionB) / factorB));
  lanes::store(current_.variance.row(row) + x, keep(own & lanes::finite(v) & (v > 0.0f), v));
}

namespace {

/// The guides of a row for the tap loops (padded planes: x + dx in [-pad, width + pad)).
struct GuideRows {
  const float* nx;
  const float* ny;
  const float* nz;
  const float* depth;
  const float* gives;
};

/// The centre pixels' guides at x (kCount of them) and what the taps' weights need from them.
struct CentreLanes {
  lanes::F nx, ny, nz, depth, depthDx, depthDy, luminance;
  lanes::F inverseTolerance;   // 1 / luminance tolerance; 0 = no luminance weight
};

/// Edge-stopping weight (without the kernel and the `gives` mask) of the tap at offset
/// (offsetX, offsetY), whose guides at the centre's pixels are (nx, ny, nz, depth) and whose
/// luminance is luminanceQ: normal, depth and (where inverseTolerance > 0) luminance.
inline lanes::F tapExp(const CentreLanes& c, lanes::F nx, lanes::F ny, lanes::F nz, lanes::F depth,
                       lanes::F luminanceQ, float offsetX, float offsetY, float sigmaNormal, float sigmaDepth) {
  const lanes::F dot = c.nx * nx + c.ny * ny + c.nz * nz;
  const lanes::F expected = absolute(c.depthDx * offsetX) + absolute(c.depthDy * offsetY);
  const lanes::F exponent = sigmaNormal * (dot - 1.0f) -
                            absolute(c.depth - depth) / (sigmaDepth * expected + kDepthRelativeSlack * c.depth) -
                            absolute(c.luminance - luminanceQ) * c.inverseTolerance;
  return negativeExp(exponent);
}

}  // namespace

Denoiser::RowScratch& Denoiser::RowScratch::sized(uint32_t width) {
  const size_t lanesWide = (size_t{width} + lanes::kCount - 1) / lanes::kCount * lanes::kCount;
  for (std::vector<float>* v : {&red, &green, &blue, &weight, &variance}) v->resize(lanesWide);
  return *this;
}

// The two row filters below take kCount pixels at a time (the last block of a row reaches past
// its end into the padding, which every plane has room for, and is stored only into the row
// scratch). Each pixel adds its taps in the same order as a pixel-by-pixel loop would, with the
// same operations: the sums are that loop's bit for bit.

void Denoiser::estimateVarianceRows(uint32_t y0, uint32_t y1) {
  const int width = static_cast<int>(width_);
  RowScratch& scratch = rowScratch_.local().sized(width_);
  const float sigmaNormal = config_.sigmaNormal, sigmaDepth = config_.sigmaDepth;
  for (uint32_t y = y0; y < y1; ++y) {
    const int row = static_cast<int>(y);
    GuideRows taps[2 * kVarianceRadius + 1];
    const float *red[2 * kVarianceRadius + 1], *green[2 * kVarianceRadius + 1], *blue[2 * kVarianceRadius + 1];
    for (int dy = -kVarianceRadius; dy <= kVarianceRadius; ++dy) {
      const int q = row + dy, k = dy + kVarianceRadius;
      taps[k] = GuideRows{normalX_.row(q), normalY_.row(q), normalZ_.row(q), depth_.row(q), gives_.row(q)};
      red[k] = current_.red.row(q);
      green[k] = current_.green.row(q);
      blue[k] = current_.blue.row(q);
    }
    const GuideRows& centre = taps[kVarianceRadius];
    const float *depthDx = depthDx_.row(row), *depthDy = depthDy_.row(row);
    const float *own = ownVariance_.row(row), *gives = centre.gives;
    for (int x = 0; x < width; x += lanes::kCount) {
      const lanes::I estimated = ~(lanes::load(own + x) > 0.0f) & (lanes::load(gives + x) > 0.0f);
      if (!lanes::any(estimated)) {
        // Each pixel here keeps the variance its history measured, or has none (below): nothing to estimate.
        lanes::store(scratch.red.data() + x, lanes::splat(0.0f));
        lanes::store(scratch.weight.data() + x, lanes::splat(1.0f));
        lanes::store(scratch.variance.data() + x, lanes::splat(0.0f));
        continue;
      }
      const lanes::F centreRed = lanes::load(red[kVarianceRadius] + x);
      const lanes::F centreGreen = lanes::load(green[kVarianceRadius] + x);
      const lanes::F centreBlue = lanes::load(blue[kVarianceRadius] + x);
      // The centre's inverseTolerance is 0: geometric weights only.
      const CentreLanes c{lanes::load(centre.nx + x),    lanes::load(centre.ny + x),
                          lanes::load(centre.nz + x),    lanes::load(centre.depth + x),
                          lanes::load(depthDx + x),      lanes::load(depthDy + x),
                          luminance(centreRed, centreGreen, centreBlue), lanes::splat(0.0f)};
      lanes::F sum = lanes::splat(0.0f), weight = sum, squares = sum;
      for (int dy = -kVarianceRadius; dy <= kVarianceRadius; ++dy) {
        const int k = dy + kVarianceRadius;
        const GuideRows& t = taps[k];
        for (int dx = -kVarianceRadius; dx <= kVarianceRadius; ++dx) {
          const int at = x + dx;
          const lanes::F l = luminance(lanes::load(red[k] + at), lanes::load(green[k] + at), lanes::load(blue[k] + at));
          const lanes::F w = 1.0f * lanes::load(t.gives + at) *
                             tapExp(c, lanes::load(t.nx + at), lanes::load(t.ny + at), lanes::load(t.nz + at),
                                    lanes::load(t.depth + at), l, static_cast<float>(dx), static_cast<float>(dy),
                                    sigmaNormal, sigmaDepth);
          sum += w * l;
          weight += w;
          squares += w * l * l;
        }
      }
      lanes::store(scratch.red.data() + x, sum);
      lanes::store(scratch.weight.data() + x, weight);
      lanes::store(scratch.variance.data() + x, squares);
    }
    const float* given = current_.variance.row(row);
    float* out = next_.variance.row(row);
    // As filterRows' last loop: kCount pixels at a time while they fit in the row, then one by one.
    int x = 0;
    for (; x + lanes::kCount <= width; x += lanes::kCount) {
      const lanes::F inverse = 1.0f / maxOf(lanes::load(scratch.weight.data() + x), lanes::splat(1e-30f));
      const lanes::F mean = lanes::load(scratch.red.data() + x) * inverse;
      const lanes::F variance = lanes::load(scratch.variance.data() + x) * inverse - mean * mean;
      const lanes::F estimated =
          lanes::select((lanes::load(gives + x) > 0.0f) & (variance > 0.0f), variance, lanes::splat(0.0f));
      lanes::store(out + x, lanes::select(lanes::load(own + x) > 0.0f, lanes::load(given + x), estimated));
    }
    for (; x < width; ++x) {
      const float inverse = 1.0f / std::max(scratch.weight[x], 1e-30f);
      const float mean = scratch.red[x] * inverse;
      const float variance = scratch.variance[x] * inverse - mean * mean;
      const float estimated = (gives[x] > 0.0f) & (variance > 0.0f) ? variance : 0.0f;
      out[x] = own[x] > 0.0f ? given[x] : estimated;
    }
  }
}

void Denoiser::filterRows(uint32_t step, uint32_t y0, uint32_t y1) {
  const int width = static_cast<int>(width_);
  const int s = static_cast<int>(step);
  RowScratch& scratch = rowScratch_.local().sized(width_);
  const float sigmaNormal = config_.sigmaNormal, sigmaDepth = config_.sigmaDepth;
  const float sigmaLuminance = config_.sigmaLuminance;
  for (uint32_t y = y0; y < y1; ++y) {
    const int row = static_cast<int>(y);
    GuideRows taps[3];
    const float *red[3], *green[3], *blue[3], *variance[3], *near[3], *nearVariance[3];
    for (int dy = -1; dy <= 1; ++dy) {
      const int q = row + dy * s;
      taps[dy + 1] = GuideRows{normalX_.row(q), normalY_.row(q), normalZ_.row(q), depth_.row(q), gives_.row(q)};
      red[dy + 1] = current_.red.row(q);
      green[dy + 1] = current_.green.row(q);
      blue[dy + 1] = current_.blue.row(q);
      variance[dy + 1] = current_.variance.row(q);
      near[dy + 1] = gives_.row(row + dy);   // the variance blur's rows: step 1
      nearVariance[dy + 1] = current_.variance.row(row + dy);
    }
    const GuideRows& centre = taps[1];
    const float *depthDx = depthDx_.row(row), *depthDy = depthDy_.row(row);
    const float* takes = takes_.row(row);
    for (int x = 0; x < width; x += lanes::kCount) {
      if (!lanes::any(lanes::load(takes + x) > 0.0f)) {
        // No pixel here is filtered (sky, black albedo): each takes 0 below, whatever its sums.
        lanes::store(scratch.weight.data() + x, lanes::splat(0.0f));
        continue;
      }
      // Noise of each pixel: 3 x 3 blur of the variance over valid pixels, as a luminance tolerance.
      lanes::F blurWeight = lanes::splat(0.0f), blurred = blurWeight;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const float k = kKernel[dx + 1] * kKernel[dy + 1];
          const lanes::F gives = lanes::load(near[dy + 1] + x + dx);
          blurWeight += k * gives;
          blurred += k * gives * lanes::load(nearVariance[dy + 1] + x + dx);
        }
      }
      const lanes::F sigma =
          sigmaLuminance * lanes::sqrt(maxOf(blurred, lanes::splat(0.0f)) / maxOf(blurWeight, lanes::splat(1e-30f)));
      const lanes::F centreRed = lanes::load(red[1] + x);
      const lanes::F centreGreen = lanes::load(green[1] + x);
      const lanes::F centreBlue = lanes::load(blue[1] + x);
      // A hole (gives = 0) has no luminance of its own yet: only geometry decides.
      const CentreLanes c{lanes::load(centre.nx + x), lanes::load(centre.ny + x),
                          lanes::load(centre.nz + x), lanes::load(centre.depth + x),
                          lanes::load(depthDx + x),   lanes::load(depthDy + x),
                          luminance(centreRed, centreGreen, centreBlue),
                          lanes::load(centre.gives + x) / (sigma + kLuminanceEpsilon)};
      lanes::F sumRed = lanes::splat(0.0f), sumGreen = sumRed, sumBlue = sumRed, weight = sumRed, sumVariance = sumRed;
      for (int dy = -1; dy <= 1; ++dy) {
        const GuideRows& t = taps[dy + 1];
        for (int dx = -1; dx <= 1; ++dx) {
          const int at = x + dx * s;
          const lanes::F r = lanes::load(red[dy + 1] + at), g = lanes::load(green[dy + 1] + at),
                         b = lanes::load(blue[dy + 1] + at);
          const lanes::F w = kKernel[dx + 1] * kKernel[dy + 1] * lanes::load(t.gives + at) *
                             tapExp(c, lanes::load(t.nx + at), lanes::load(t.ny + at), lanes::load(t.nz + at),
                                    lanes::load(t.depth + at), luminance(r, g, b), static_cast<float>(dx * s),
                                    static_cast<float>(dy * s), sigmaNormal, sigmaDepth);
          sumRed += w * r;
          sumGreen += w * g;
          sumBlue += w * b;
          weight += w;
          sumVariance += w * w * lanes::load(variance[dy + 1] + at);
        }
      }
      lanes::store(scratch.red.data() + x, sumRed);
      lanes::store(scratch.green.data() + x, sumGreen);
      lanes::store(scratch.blue.data() + x, sumBlue);
      lanes::store(scratch.weight.data() + x, weight);
      lanes::store(scratch.variance.data() + x, sumVariance);
    }
    float* outRed = next_.red.row(row);
    float* outGreen = next_.green.row(row);
    float* outBlue = next_.blue.row(row);
    float* outVariance = next_.variance.row(row);
    // kCount pixels at a time while they fit in the row (the planes' padding stays zero), then
    // one by one; the same operations either way.
    int x = 0;
    for (; x + lanes::kCount <= width; x += lanes::kCount) {
      const lanes::F weight = lanes::load(scratch.weight.data() + x);
      const lanes::I filtered = (lanes::load(takes + x) > 0.0f) & (weight > 0.0f);
      const lanes::F inverse = 1.0f / maxOf(weight, lanes::splat(1e-30f));
      const lanes::F zero = lanes::splat(0.0f);
      lanes::store(outRed + x, lanes::select(filtered, lanes::load(scratch.red.data() + x) * inverse, zero));
      lanes::store(outGreen + x, lanes::select(filtered, lanes::load(scratch.green.data() + x) * inverse, zero));
      lanes::store(outBlue + x, lanes::select(filtered, lanes::load(scratch.blue.data() + x) * inverse, zero));
      lanes::store(outVariance + x,
                   lanes::select(filtered, lanes::load(scratch.variance.data() + x) * inverse * inverse, zero));
    }
    for (; x < width; ++x) {
      const bool filtered = (takes[x] > 0.0f) & (scratch.weight[x] > 0.0f);
      const float inverse = 1.0f / std::max(scratch.weight[x], 1e-30f);
      outRed[x] = filtered ? scratch.red[x] * inverse : 0.0f;
      outGreen[x] = filtered ? scratch.green[x] * inverse : 0.0f;
      outBlue[x] = filtered ? scratch.blue[x] * inverse : 0.0f;
      outVariance[x] = filtered ? scratch.variance[x] * inverse * inverse : 0.0f;
    }
  }
}

}  // namespace pa::denoise
