#include "renderer/scene/temporal/temporal.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "renderer/core/finite.h"
#include "renderer/scene/sampling/warp.h"
#include "renderer/scene/taau/lanes.h"

namespace pa::temporal {
namespace {

/// As the denoiser: albedo below this per channel is raised to it to demodulate, and a pixel
/// with every channel below it (black) is not accumulated.
constexpr float kMinAlbedo = 1e-3f;
/// Half-size of the neighbourhood of the history-rejection test (5 x 5).
constexpr int kRejectRadius = 2;
/// A neighbour's luminance change counts at most this many of its standard deviations ...
constexpr float kChangeClampSigmas = 3.0f;
/// ... plus this fraction of its history's luminance (rejection test).
constexpr float kChangeClampRelative = 0.2f;
/// Least total bilinear weight of the valid taps for a history to count.
constexpr float kMinTapWeight = 1e-3f;
/// Zero border of the rejection planes: the test's radius.
constexpr size_t kRejectPad = kRejectRadius;
/// Rows per parallel task.
constexpr uint32_t kRowGrain = 4;

using sampling::luminance;

glm::vec3 demodulationFactor(const glm::vec3& albedo) { return glm::max(albedo, glm::vec3(kMinAlbedo)); }

/// Depth change per pixel towards the neighbour on the same surface (the smaller change); 0 with none.
float depthSlope(float here, float before, float after) {
  const bool hasBefore = std::isfinite(before) && before > 0.0f;
  const bool hasAfter = std::isfinite(after) && after > 0.0f;
  if (hasBefore && hasAfter) return std::min(std::abs(here - before), std::abs(after - here));
  if (hasBefore) return std::abs(here - before);
  if (hasAfter) return std::abs(after - here);
  return 0.0f;
}

/// Per lane, |v| as std::abs gives it (the sign bit cleared).
inline taau::lanes::F absolute(taau::lanes::F v) {
  return std::bit_cast<taau::lanes::F>(std::bit_cast<taau::lanes::I>(v) & taau::lanes::splat(int32_t{0x7fffffff}));
}

template <typename Body>
void parallelRows(uint32_t height, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, height, kRowGrain),
                    [&](const tbb::blocked_range<uint32_t>& r) { body(r.begin(), r.end()); });
}

}  // namespace

TemporalFilter::TemporalFilter(const Config& config) : config_(config) {
  config_.alphaMin = std::clamp(std::isfinite(config_.alphaMin) ? config_.alphaMin : 0.1f, 1e-3f, 1.0f);
  config_.momentsAlphaMin =
      std::clamp(std::isfinite(config_.momentsAlphaMin) ? config_.momentsAlphaMin : 0.2f, 1e-3f, 1.0f);
  config_.maxHistory = std::max(1.0f, std::isfinite(config_.maxHistory) ? config_.maxHistory : 64.0f);
}

void TemporalFilter::reset() { haveHistory_ = false; }

void TemporalFilter::accumulate(const FrameInputs& frame, std::span<glm::vec3> radiance) {
  const size_t n = size_t{frame.width} * frame.height;
  const auto check = [n](size_t size, const char* name) {
    if (size != n) {
      throw std::invalid_argument(std::string("temporal: ") + name + " has " + std::to_string(size) +
                                  " pixels, expected " + std::to_string(n));
    }
  };
  check(radiance.size(), "radiance");
  check(frame.emission.size(), "emission");
  check(frame.albedo.size(), "albedo");
  check(frame.normal.size(), "normal");
  check(frame.depth.size(), "depth");
  if (!frame.historyDrop.empty()) check(frame.historyDrop.size(), "historyDrop");
  if (frame.gbuffer == nullptr) throw std::invalid_argument("temporal: no G-buffer");
  check(frame.gbuffer->instance.size(), "G-buffer");
  if (frame.gbuffer->width != frame.width || frame.gbuffer->height != frame.height) {
    throw std::invalid_argument("temporal: G-buffer size differs from the frame's");
  }
  if (frame.width != width_ || frame.height != height_) {
    width_ = frame.width;
    height_ = frame.height;
    haveHistory_ = false;
    color_.assign(n, glm::vec3(0.0f));
    historyColor_.assign(n, glm::vec3(0.0f));
    state_.assign(n, State{});
    history_.assign(n, State{});
    variance_.assign(n, 0.0f);
    length_.assign(n, 0.0f);
    signal_.assign(n, glm::vec3(0.0f));
    signalLuminance_.assign(n, 0.0f);
    reprojected_.assign(n, Reprojected{});
    // The border stays zero; kCount more floats let a row's last block of lanes read past the
    // end of the last padded row.
    reject_.pad = kRejectPad;
    reject_.stride = frame.width + 2 * kRejectPad;
    const size_t planeSize = reject_.stride * (frame.height + 2 * kRejectPad) + taau::lanes::kCount;
    for (std::vector<float>* plane : {&reject_.change, &reject_.mean, &reject_.variance, &reject_.count})
      plane->assign(planeSize, 0.0f);
    const size_t lanesWide = (size_t{frame.width} + taau::lanes::kCount - 1) / taau::lanes::kCount * taau::lanes::kCount;
    rejected_.assign(lanesWide * frame.height, 0);
  }
  if (n == 0) return;
  parallelRows(frame.height, [&](uint32_t y0, uint32_t y1) { prepareRows(frame, radiance, y0, y1); });
  parallelRows(frame.height, [&](uint32_t y0, uint32_t y1) { reprojectRows(frame, y0, y1); });
  parallelRows(frame.height, [&](uint32_t y0, uint32_t y1) { blendRows(frame, radiance, y0, y1); });
}

void TemporalFilter::endFrame() {
  if (width_ == 0 || height_ == 0) return;
  std::swap(color_, historyColor_);
  std::swap(state_, history_);
  haveHistory_ = true;
}

void TemporalFilter::prepareRows(const FrameInputs& frame, std::span<const glm::vec3> radiance, uint32_t y0,
                                 uint32_t y1) {
  const float none = std::numeric_limits<float>::quiet_NaN();
  for (size_t i = size_t{y0} * frame.width; i < size_t{y1} * frame.width; ++i) {
    const float z = frame.depth[i];
    const glm::vec3 albedo = frame.albedo[i];
    const glm::vec3 normal = frame.normal[i];
    const bool geometry = std::isfinite(z) && z > 0.0f && finite(albedo) && finite(normal) &&
                          glm::length(normal) > 1e-6f && std::max({albedo.x, albedo.y, albedo.z}) >= kMinAlbedo &&
                          finite(radiance[i]);
    if (!geometry) {
      signalLuminance_[i] = none;
      continue;
    }
    const glm::vec3 emission = finite(frame.emission[i]) ? frame.emission[i] : glm::vec3(0.0f);
    signal_[i] = (radiance[i] - emission) / demodulationFactor(albedo);
    signalLuminance_[i] = luminance(signal_[i]);
  }
}

void TemporalFilter::reprojectRows(const FrameInputs& frame, uint32_t y0, uint32_t y1) {
  // Pixels with all four neighbours inside the frame kCount at a time, the others (and the few
  // lanes that need the 3 x 3 fallback) one by one: the same operations in the same order.
  const uint32_t width = frame.width;
  for (uint32_t y = y0; y < y1; ++y) {
    uint32_t x = 0;
    if (config_.rowLanes && haveHistory_ && y > 0 && y + 1 < frame.height && width > taau::lanes::kCount + 1) {
      reprojectPixel(frame, 0, y);
      for (x = 1; x + taau::lanes::kCount < width; x += taau::lanes::kCount) reprojectLanes(frame, x, y);
    }
    for (; x < width; ++x) reprojectPixel(frame, x, y);
  }
}

void TemporalFilter::reprojectPixel(const FrameInputs& frame, uint32_t x, uint32_t y) {
  const GBuffer& g = *frame.gbuffer;
  const int width = static_cast<int>(frame.width), height = static_cast<int>(frame.height);
  const auto depthAt = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < width && y < height ? frame.depth[size_t(y) * frame.width + size_t(x)]
                                                       : std::numeric_limits<float>::infinity();
  };
  const size_t i = size_t{y} * frame.width + x;
  Reprojected& out = reprojected_[i];
  out = Reprojected{};
  const size_t terms = reject_.at(x, y);
  reject_.change[terms] = reject_.mean[terms] = reject_.variance[terms] = reject_.count[terms] = 0.0f;
  const glm::vec2 motion = g.motion[i];
  if (!haveHistory_ || !std::isfinite(signalLuminance_[i]) || !std::isfinite(motion.x) ||
      !std::isfinite(motion.y)) {
    return;
  }
  const int xi = static_cast<int>(x), yi = static_cast<int>(y);
  const float z = frame.depth[i];
  const float slope = depthSlope(z, depthAt(xi - 1, yi), depthAt(xi + 1, yi)) +
                      depthSlope(z, depthAt(xi, yi - 1), depthAt(xi, yi + 1));
  const float expectedDepth = g.previousDepth[i];
  const float depthTolerance = config_.depthTolerance * expectedDepth + 2.0f * slope;
  const glm::vec3 expectedNormal = g.previousNormal[i];
  // Bilinear taps around the previous position of the pixel's centre.
  const float fx = static_cast<float>(x) + motion.x, fy = static_cast<float>(y) + motion.y;
  const float bx = std::floor(fx), by = std::floor(fy);
  if (!(bx > -2.0f && by > -2.0f && bx < static_cast<float>(width) + 1.0f &&
        by < static_cast<float>(height) + 1.0f)) {
    return;
  }
  const int x0 = static_cast<int>(bx), ty0 = static_cast<int>(by);
  const float tx = fx - bx, ty = fy - by;
  float weight = 0.0f;
  // Adds history pixel (px, py) with weight w when it shows the same surface as this pixel.
  const auto addTap = [&](int px, int py, float w) {
    if (px < 0 || py < 0 || px >= width || py >= height || !(w > 0.0f)) return;
    const size_t j = size_t(py) * frame.width + size_t(px);
    const State& h = history_[j];
    if (!(h.length > 0.0f) || h.instance != g.instance[i] || h.material != g.material[i]) return;
    if (!(std::abs(h.depth - expectedDepth) <= depthTolerance)) return;
    if (!(glm::dot(h.normal, expectedNormal) >= config_.normalCosine)) return;
    out.color += w * historyColor_[j];
    out.moment1 += w * h.moment1;
    out.moment2 += w * h.moment2;
    out.length += w * h.length;
    weight += w;
  };
  for (int dy = 0; dy <= 1; ++dy)
    for (int dx = 0; dx <= 1; ++dx)
      addTap(x0 + dx, ty0 + dy, (dx != 0 ? tx : 1.0f - tx) * (dy != 0 ? ty : 1.0f - ty));
  if (weight < kMinTapWeight) {
    // No bilinear tap shows this surface (at an edge the jittered sample may hit the other
    // side of it than last frame's did): as SVGF, any pixel of the 3 x 3 around the previous
    // position that does, equally weighted.
    out = Reprojected{};
    weight = 0.0f;
    const int cx = static_cast<int>(std::floor(fx + 0.5f)), cy = static_cast<int>(std::floor(fy + 0.5f));
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) addTap(cx + dx, cy + dy, 1.0f);
  }
  if (weight < kMinTapWeight) {
    out = Reprojected{};
    return;
  }
  const float inverse = 1.0f / weight;
  out.color *= inverse;
  out.moment1 *= inverse;
  out.moment2 *= inverse;
  out.length *= inverse;
  out.variance = std::max(0.0f, out.moment2 - out.moment1 * out.moment1);
  if (!(out.length > 0.0f)) return;
  // The largest luminance change this pixel adds to its neighbours' rejection tests.
  const float changeBound =
      kChangeClampSigmas * std::sqrt(out.variance) + kChangeClampRelative * std::abs(out.moment1) + 1e-6f;
  reject_.change[terms] = std::clamp(signalLuminance_[i] - out.moment1, -changeBound, changeBound);
  reject_.mean[terms] = out.moment1;
  reject_.variance[terms] = out.variance;
  reject_.count[terms] = 1.0f;
}

void TemporalFilter::reprojectLanes(const FrameInputs& frame, uint32_t x, uint32_t y) {
  namespace lanes = taau::lanes;
  using lanes::F;
  using lanes::I;
  const GBuffer& g = *frame.gbuffer;
  const uint32_t width = frame.width;
  const size_t i = size_t{y} * width + x;
  const F zero = lanes::splat(0.0f);
  const F luminanceHere = lanes::load(signalLuminance_.data() + i);
  const float* motion = &g.motion[i].x;
  const F motionX = lanes::gather(motion, lanes::kIota * 2), motionY = lanes::gather(motion + 1, lanes::kIota * 2);
  const float* depth = frame.depth.data() + i;
  const F z = lanes::load(depth);
  // depthSlope(here, before, after).
  const auto slopeOf = [&](F before, F after) {
    const I hasBefore = lanes::finite(before) & (before > 0.0f);
    const I hasAfter = lanes::finite(after) & (after > 0.0f);
    const F toBefore = absolute(z - before), toAfter = absolute(after - z);
    return lanes::select(hasBefore & hasAfter, lanes::min(toBefore, toAfter),
                         lanes::select(hasBefore, toBefore, lanes::select(hasAfter, toAfter, zero)));
  };
  const F slope = slopeOf(lanes::load(depth - 1), lanes::load(depth + 1)) +
                  slopeOf(lanes::load(depth - width), lanes::load(depth + width));
  const F expectedDepth = lanes::load(g.previousDepth.data() + i);
  const F depthTolerance = config_.depthTolerance * expectedDepth + 2.0f * slope;
  const float* previousNormal = &g.previousNormal[i].x;
  const F expectedX = lanes::gather(previousNormal, lanes::kIota * 3);
  const F expectedY = lanes::gather(previousNormal + 1, lanes::kIota * 3);
  const F expectedZ = lanes::gather(previousNormal + 2, lanes::kIota * 3);
  const I instance = lanes::load(reinterpret_cast<const int32_t*>(g.instance.data() + i));
  const I material = lanes::load(reinterpret_cast<const int32_t*>(g.material.data() + i));
  // Bilinear taps around the previous position of the pixel's centre.
  const F fx = lanes::toFloat(lanes::splat(static_cast<int32_t>(x)) + lanes::kIota) + motionX;
  const F fy = static_cast<float>(y) + motionY;
  const F bx = lanes::select(lanes::finite(fx), fx, zero), by = lanes::select(lanes::finite(fy), fy, zero);
  const I x0 = lanes::floorToInt(lanes::clamp(bx, lanes::splat(-4.0f), lanes::splat(static_cast<float>(width) + 4.0f)));
  const I y0 = lanes::floorToInt(
      lanes::clamp(by, lanes::splat(-4.0f), lanes::splat(static_cast<float>(frame.height) + 4.0f)));
  const F floorX = lanes::toFloat(x0), floorY = lanes::toFloat(y0);
  const I active = lanes::finite(luminanceHere) & lanes::finite(motionX) & lanes::finite(motionY) &
                   (floorX > -2.0f) & (floorY > -2.0f) & (floorX < static_cast<float>(width) + 1.0f) &
                   (floorY < static_cast<float>(frame.height) + 1.0f);
  const F tx = fx - floorX, ty = fy - floorY;
  F red = zero, green = zero, blue = zero, moment1 = zero, moment2 = zero, length = zero, weight = zero;
  static_assert(sizeof(State) == 9 * sizeof(float), "State is read as 9 floats");
  const float* history = reinterpret_cast<const float*>(history_.data());
  const float* historyColor = &historyColor_[0].x;
  for (int dy = 0; dy <= 1; ++dy) {
    for (int dx = 0; dx <= 1; ++dx) {
      const F w = (dx != 0 ? tx : 1.0f - tx) * (dy != 0 ? ty : 1.0f - ty);
      const I px = x0 + dx, py = y0 + dy;
      const I inside = active & (px >= 0) & (py >= 0) & (px < static_cast<int32_t>(width)) &
                       (py < static_cast<int32_t>(frame.height)) & (w > 0.0f);
      const I j = lanes::select(inside, py * static_cast<int32_t>(width) + px, lanes::splat(int32_t{0}));
      const I state = j * 9;
      const F hLength = lanes::gather(history, state + 2);
      const F hDepth = lanes::gather(history, state + 3);
      const F hNormalX = lanes::gather(history, state + 4), hNormalY = lanes::gather(history, state + 5),
              hNormalZ = lanes::gather(history, state + 6);
      const I hInstance = lanes::gather(reinterpret_cast<const int32_t*>(history), state + 7);
      const I hMaterial = lanes::gather(reinterpret_cast<const int32_t*>(history), state + 8);
      const I same = inside & (hLength > 0.0f) & (hInstance == instance) & (hMaterial == material) &
                     (absolute(hDepth - expectedDepth) <= depthTolerance) &
                     (hNormalX * expectedX + hNormalY * expectedY + hNormalZ * expectedZ >= config_.normalCosine);
      if (!lanes::any(same)) continue;
      const I color = j * 3;
      red = lanes::select(same, red + w * lanes::gather(historyColor, color), red);
      green = lanes::select(same, green + w * lanes::gather(historyColor, color + 1), green);
      blue = lanes::select(same, blue + w * lanes::gather(historyColor, color + 2), blue);
      moment1 = lanes::select(same, moment1 + w * lanes::gather(history, state), moment1);
      moment2 = lanes::select(same, moment2 + w * lanes::gather(history, state + 1), moment2);
      length = lanes::select(same, length + w * hLength, length);
      weight = lanes::select(same, weight + w, weight);
    }
  }
  const I kept = active & (weight >= kMinTapWeight);
  const F inverse = 1.0f / lanes::select(kept, weight, lanes::splat(1.0f));
  red *= inverse;
  green *= inverse;
  blue *= inverse;
  moment1 *= inverse;
  moment2 *= inverse;
  length *= inverse;
  const F difference = moment2 - moment1 * moment1;
  const F variance = lanes::select(zero < difference, difference, zero);   // std::max(0, difference)
  const F changeBound = kChangeClampSigmas * lanes::sqrt(variance) + kChangeClampRelative * absolute(moment1) + 1e-6f;
  const I counted = kept & (length > 0.0f);
  const size_t terms = reject_.at(x, y);
  lanes::store(reject_.change.data() + terms,
               lanes::select(counted, lanes::clamp(luminanceHere - moment1, -changeBound, changeBound), zero));
  lanes::store(reject_.mean.data() + terms, lanes::select(counted, moment1, zero));
  lanes::store(reject_.variance.data() + terms, lanes::select(counted, variance, zero));
  lanes::store(reject_.count.data() + terms, lanes::select(counted, lanes::splat(1.0f), zero));
  for (int k = 0; k < lanes::kCount; ++k) {
    Reprojected& out = reprojected_[i + k];
    if (kept[k] != 0) {
      out = Reprojected{glm::vec3(red[k], green[k], blue[k]), moment1[k], moment2[k], length[k], variance[k]};
    } else if (active[k] != 0) {
      reprojectPixel(frame, x + k, y);   // no bilinear tap: the 3 x 3 fallback
    } else {
      out = Reprojected{};
    }
  }
}

void TemporalFilter::rejectRow(uint32_t y, int32_t* out) const {
  // This frame's luminance minus the history's mean, over the neighbours that have a history, is
  // noise around 0 while the lighting holds. Each neighbour's change is clamped to 3 of its own
  // standard deviations plus 20% of its history (a Huber-like mean): a few fireflies in the
  // neighbourhood must not drop 25 histories, while a change the whole neighbourhood shares still
  // shows. kCount pixels at a time; neighbours without history (or outside the frame) add zeros,
  // which leaves every sum as adding only the others would.
  namespace lanes = taau::lanes;
  for (uint32_t x = 0; x < width_; x += lanes::kCount) {
    lanes::F change = lanes::splat(0.0f), historySum = change, varianceSum = change, count = change;
    for (int dy = -kRejectRadius; dy <= kRejectRadius; ++dy) {
      const size_t row = reject_.at(x, y) + dy * static_cast<std::ptrdiff_t>(reject_.stride);
      for (int dx = -kRejectRadius; dx <= kRejectRadius; ++dx) {
        const size_t j = row + dx;
        change += lanes::load(reject_.change.data() + j);
        historySum += lanes::load(reject_.mean.data() + j);
        varianceSum += lanes::load(reject_.variance.data() + j);
        count += lanes::load(reject_.count.data() + j);
      }
    }
    const lanes::F meanChange = change / count;   // count >= 1 where the pixel has a history
    const lanes::F tolerance = config_.rejectSigmas * lanes::sqrt(varianceSum / count / count) +
                               config_.rejectRelative * lanes::abs(historySum / count) + 1e-6f;
    lanes::store(out + x, lanes::abs(meanChange) > tolerance);
  }
}

void TemporalFilter::blendRows(const FrameInputs& frame, std::span<glm::vec3> radiance, uint32_t y0, uint32_t y1) {
  const GBuffer& g = *frame.gbuffer;
  const bool hasDrop = !frame.historyDrop.empty();
  const size_t rejectedStride = (size_t{frame.width} + taau::lanes::kCount - 1) / taau::lanes::kCount * taau::lanes::kCount;
  for (uint32_t y = y0; y < y1; ++y) {
    int32_t* rejected = rejected_.data() + y * rejectedStride;
    rejectRow(y, rejected);
    for (uint32_t x = 0; x < frame.width; ++x) {
      const size_t i = size_t{y} * frame.width + x;
      State& out = state_[i];
      const float l = signalLuminance_[i];
      if (!std::isfinite(l)) {   // sky, black or broken: passes through with no history
        out = State{};
        color_[i] = glm::vec3(0.0f);
        variance_[i] = 0.0f;
        length_[i] = 0.0f;
        continue;
      }
      Reprojected history = reprojected_[i];
      // Rejection (rejectRow): the neighbourhood's luminance changes say the lighting changed.
      if (history.length >= static_cast<float>(config_.minLengthForVariance) && rejected[x] != 0) history = Reprojected{};
      // Temporal gradients: the share of the history the changed lighting makes stale (A-SVGF's
      // alpha' = (1 - drop) alpha + drop); the length left shrinks with it.
      const float drop = hasDrop ? std::clamp(frame.historyDrop[i], 0.0f, 1.0f) : 0.0f;
      if (drop >= 1.0f) history = Reprojected{};
      glm::vec3 color = signal_[i];
      float moment1 = l, moment2 = l * l, length = 1.0f;
      float meanShare = 1.0f;   // variance of the blended colour per unit of one sample's variance
      if (history.length > 0.0f) {
        length = std::min(history.length * (1.0f - drop) + 1.0f, config_.maxHistory);
        float alpha = std::max(1.0f / length, config_.alphaMin);
        alpha += drop * (1.0f - alpha);
        meanShare = std::max(alpha / (2.0f - alpha), 1.0f / length);
        float alphaMoments = std::max(1.0f / length, config_.momentsAlphaMin);
        alphaMoments += drop * (1.0f - alphaMoments);
        color = glm::mix(history.color, color, alpha);
        moment1 = glm::mix(history.moment1, moment1, alphaMoments);
        moment2 = glm::mix(history.moment2, moment2, alphaMoments);
      }
      const glm::vec3 factor = demodulationFactor(frame.albedo[i]);
      const glm::vec3 emission = finite(frame.emission[i]) ? frame.emission[i] : glm::vec3(0.0f);
      radiance[i] = color * factor + emission;
      const float scale = luminance(factor);
      variance_[i] = length >= static_cast<float>(config_.minLengthForVariance)
                         ? std::max(0.0f, moment2 - moment1 * moment1) * meanShare * scale * scale
                         : 0.0f;
      length_[i] = length;
      color_[i] = color;
      const glm::vec3 normal = frame.normal[i];
      out = State{moment1, moment2, length, frame.depth[i], normal / glm::length(normal), g.instance[i],
                  g.material[i]};
    }
  }
}

}  // namespace pa::temporal
