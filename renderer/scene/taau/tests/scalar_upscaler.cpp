// The scalar TAAU resolve, unchanged but for its name: see scalar_upscaler.h.
#include "scalar_upscaler.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/geometric.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace pa::taau::test {
namespace {

constexpr uint32_t kRowGrain = 8;        // rows per parallel task

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

float linearToSrgb(float c) { return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f; }

glm::vec3 toYCoCg(const glm::vec3& c) {
  return {0.25f * c.r + 0.5f * c.g + 0.25f * c.b, 0.5f * c.r - 0.5f * c.b, -0.25f * c.r + 0.5f * c.g - 0.25f * c.b};
}

glm::vec3 fromYCoCg(const glm::vec3& c) { return {c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z}; }

/// Catmull-Rom weights of the four taps around a position t in [0, 1) past the second one.
std::array<float, 4> catmullRom(float t) {
  const float t2 = t * t;
  return {t * (-0.5f + t * (1.0f - 0.5f * t)), 1.0f + t2 * (-2.5f + 1.5f * t), t * (0.5f + t * (2.0f - 1.5f * t)),
          t2 * (-0.5f + 0.5f * t)};
}

/// Four floats in one SIMD register (GCC / Clang vector extension).
typedef float Lanes __attribute__((vector_size(16)));

Lanes load(const glm::vec4& v) {
  Lanes l;
  std::memcpy(&l, &v, sizeof l);
  return l;
}

template <class Body>
void parallelRows(uint32_t height, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, height, kRowGrain),
                    [&](const tbb::blocked_range<uint32_t>& r) { body(r.begin(), r.end()); });
}

}  // namespace

ScalarUpscaler::ScalarUpscaler(const Config& config) : config_(config) {
  for (uint32_t i = 0; i < 256; ++i) decode_[i] = srgbToLinear(static_cast<float>(i) / 255.0f);
  for (uint32_t i = 0; i < kEncodeSteps; ++i) {
    const float s = static_cast<float>(i) / static_cast<float>(kEncodeSteps - 1);
    encode_[i] = static_cast<uint8_t>(std::lround(std::clamp(linearToSrgb(s * s), 0.0f, 1.0f) * 255.0f));
  }
}

uint8_t ScalarUpscaler::encode(float linear) const {
  const float s = std::sqrt(std::clamp(linear, 0.0f, 1.0f));
  return encode_[static_cast<uint32_t>(s * static_cast<float>(kEncodeSteps - 1) + 0.5f)];
}

void ScalarUpscaler::reset() { haveHistory_ = false; }

std::span<const uint8_t> ScalarUpscaler::resolve(const Frame& frame, uint32_t outWidth, uint32_t outHeight) {
  const size_t traced = size_t{frame.width} * frame.height;
  if (outWidth == 0 || outHeight == 0 || traced == 0 || frame.rgba8.size() != traced * 4 ||
      frame.motion.size() != traced || frame.depth.size() != traced || frame.instance.size() != traced)
    return {};
  const size_t n = size_t{outWidth} * outHeight;
  if (outWidth != outWidth_ || outHeight != outHeight_) {
    outWidth_ = outWidth;
    outHeight_ = outHeight;
    haveHistory_ = false;
    history_.assign(n, glm::vec4(0.0f));
    nextHistory_.assign(n, glm::vec4(0.0f));
    weight_.assign(n, 0.0f);
    nextWeight_.assign(n, 0.0f);
    instance_.assign(n, kNoId);
    boxLo_.assign(n, glm::vec3(0.0f));
    boxHi_.assign(n, glm::vec3(0.0f));
    nextBoxLo_.assign(n, glm::vec3(0.0f));
    nextBoxHi_.assign(n, glm::vec3(0.0f));
    nextInstance_.assign(n, kNoId);
    output_.assign(n * 4, 255);
    lastCamera_.reset();
  }
  samples_.resize(traced);
  neighbourhood_.resize(traced);
  rays_.reset();
  previousRays_.reset();
  if (frame.camera != nullptr) {
    rays_.emplace(*frame.camera, outWidth, outHeight);
    if (lastCamera_) previousRays_.emplace(*lastCamera_, outWidth, outHeight);
  }
  weightCap_ = historyWeightCap(config_, static_cast<float>(traced) / static_cast<float>(n));
  kernelTaps(frame.width, outWidth, frame.jitter.x, config_.kernelRadius, columns_, columnD2_);
  kernelTaps(frame.height, outHeight, frame.jitter.y, config_.kernelRadius, rows_, rowD2_);
  movingRadius_ = movingKernelRadius(config_, frame.width, frame.height, outWidth, outHeight);
  kernelTaps(frame.width, outWidth, frame.jitter.x, movingRadius_, movingColumns_, movingColumnD2_);
  kernelTaps(frame.height, outHeight, frame.jitter.y, movingRadius_, movingRows_, movingRowD2_);
  parallelRows(frame.height, [&](uint32_t y0, uint32_t y1) { prepareRows(frame, y0, y1); });
  parallelRows(frame.height, [&](uint32_t y0, uint32_t y1) { neighbourhoodRows(frame, y0, y1); });
  parallelRows(outHeight, [&](uint32_t y0, uint32_t y1) { resolveRows(frame, y0, y1); });
  std::swap(history_, nextHistory_);
  std::swap(weight_, nextWeight_);
  std::swap(instance_, nextInstance_);
  std::swap(boxLo_, nextBoxLo_);
  std::swap(boxHi_, nextBoxHi_);
  haveHistory_ = true;
  if (frame.camera != nullptr) lastCamera_ = *frame.camera;
  else lastCamera_.reset();
  return output_;
}

void ScalarUpscaler::prepareRows(const Frame& frame, uint32_t y0, uint32_t y1) {
  for (uint32_t y = y0; y < y1; ++y) {
    for (uint32_t x = 0; x < frame.width; ++x) {
      const size_t i = size_t{y} * frame.width + x;
      const uint8_t* p = &frame.rgba8[i * 4];
      samples_[i] = toYCoCg({decode_[p[0]], decode_[p[1]], decode_[p[2]]});
    }
  }
}

void ScalarUpscaler::neighbourhoodRows(const Frame& frame, uint32_t y0, uint32_t y1) {
  const int w = static_cast<int>(frame.width), h = static_cast<int>(frame.height);
  for (int y = static_cast<int>(y0); y < static_cast<int>(y1); ++y) {
    for (int x = 0; x < w; ++x) {
      glm::vec3 m1(0.0f), m2(0.0f);
      float closestDepth = std::numeric_limits<float>::infinity();
      size_t closest = size_t(y) * size_t(w) + size_t(x);
      int count = 0;
      for (int iy = std::max(y - 1, 0); iy <= std::min(y + 1, h - 1); ++iy) {
        for (int ix = std::max(x - 1, 0); ix <= std::min(x + 1, w - 1); ++ix) {
          const size_t i = size_t(iy) * size_t(w) + size_t(ix);
          const glm::vec3 c = samples_[i];
          m1 += c;
          m2 += c * c;
          ++count;
          if (frame.depth[i] < closestDepth) {
            closestDepth = frame.depth[i];
            closest = i;
          }
        }
      }
      const float inv = 1.0f / static_cast<float>(count);
      Neighbourhood& n = neighbourhood_[size_t(y) * size_t(w) + size_t(x)];
      n.mean = m1 * inv;
      n.sigma = glm::sqrt(glm::max(m2 * inv - n.mean * n.mean, glm::vec3(0.0f)));
      n.closest = static_cast<uint32_t>(closest);
    }
  }
}

glm::vec3 ScalarUpscaler::bilinearSample(const Frame& frame, float fx, float fy) const {
  const int w = static_cast<int>(frame.width), h = static_cast<int>(frame.height);
  const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
  const float tx = fx - static_cast<float>(x0), ty = fy - static_cast<float>(y0);
  const size_t xa = size_t(std::clamp(x0, 0, w - 1)), xb = size_t(std::clamp(x0 + 1, 0, w - 1));
  const size_t ya = size_t(std::clamp(y0, 0, h - 1)) * size_t(w), yb = size_t(std::clamp(y0 + 1, 0, h - 1)) * size_t(w);
  const glm::vec3 top = samples_[ya + xa] + tx * (samples_[ya + xb] - samples_[ya + xa]);
  const glm::vec3 bottom = samples_[yb + xa] + tx * (samples_[yb + xb] - samples_[yb + xa]);
  return top + ty * (bottom - top);
}

void ScalarUpscaler::resolveRows(const Frame& frame, uint32_t y0, uint32_t y1) {
  const uint32_t w = frame.width, h = frame.height, W = outWidth_, H = outHeight_;
  const float sx = static_cast<float>(w) / static_cast<float>(W);   // traced pixels per output pixel
  const float sy = static_cast<float>(h) / static_cast<float>(H);
  const float invRadius2 = 1.0f / (config_.kernelRadius * config_.kernelRadius);
  const float invMovingRadius2 = 1.0f / (movingRadius_ * movingRadius_);
  const auto historyIndex = [&](int x, int y) {
    return size_t(std::clamp(y, 0, int(H) - 1)) * W + size_t(std::clamp(x, 0, int(W) - 1));
  };
  for (uint32_t oy = y0; oy < y1; ++oy) {
    for (uint32_t ox = 0; ox < W; ++ox) {
      const float cx = static_cast<float>(ox) + 0.5f, cy = static_cast<float>(oy) + 0.5f;
      const float qx = cx * sx, qy = cy * sy;   // the output pixel's centre in traced pixels
      // The sample nearest to the pixel's centre.
      const size_t centre = size_t(rows_[oy].nearest) * w + size_t(columns_[ox].nearest);
      // Its 3 x 3 neighbourhood: colour mean and deviation, the closest surface.
      const Neighbourhood& near = neighbourhood_[centre];
      const glm::vec3 mean = near.mean, sigma = near.sigma;
      const size_t closest = near.closest;
      const float closestDepth = frame.depth[closest];
      const InstanceId surface = frame.instance[closest];
      // Where this pixel was: the closest surface's motion, or the sky's under the camera's turn.
      glm::vec2 motion(std::numeric_limits<float>::quiet_NaN());
      const glm::vec2 traced = frame.motion[closest];
      if (std::isfinite(traced.x) && std::isfinite(traced.y)) {
        motion = {traced.x / sx, traced.y / sy};
      } else if (!std::isfinite(closestDepth) && rays_ && previousRays_) {
        const glm::vec3 dir = rays_->generate(cx, cy).dir;
        float px = 0.0f, py = 0.0f;
        if (previousRays_->project(previousRays_->origin() + dir, px, py)) motion = {px - cx, py - cy};
      }
      const float still = std::isfinite(motion.x) ? std::clamp(1.0f - glm::length(motion), 0.0f, 1.0f) : 0.0f;
      const float gamma = config_.clipMoving + (config_.clipStill - config_.clipMoving) * still;
      // This frame: the colour within the kernel's reach (the nearest sample where none is); a
      // moving pixel takes the wider kernel, which reaches a sample from every output pixel.
      const bool moving = still < 0.5f;
      const AxisTaps& column = moving ? movingColumns_[ox] : columns_[ox];
      const AxisTaps& row = moving ? movingRows_[oy] : rows_[oy];
      const std::vector<float>& columnD2 = moving ? movingColumnD2_ : columnD2_;
      const std::vector<float>& rowD2 = moving ? movingRowD2_ : rowD2_;
      const float invR2 = moving ? invMovingRadius2 : invRadius2;
      glm::vec3 sum(0.0f);
      float confidence = 0.0f;
      for (int a = 0; a < row.count; ++a) {
        const float dy2 = rowD2[row.offset + uint32_t(a)];
        const glm::vec3* line = &samples_[size_t(row.first + a) * w + size_t(column.first)];
        for (int b = 0; b < column.count; ++b) {
          const float u = (columnD2[column.offset + uint32_t(b)] + dy2) * invR2;
          if (u < 1.0f) {
            const float k = (1.0f - u) * (1.0f - u);
            sum += k * line[b];
            confidence += k;
          }
        }
      }
      const glm::vec3 current = confidence > 1e-4f ? sum / confidence : samples_[centre];
      glm::vec3 result;
      bool historyUsed = false;
      float weight = confidence;
      const float px = cx + motion.x, py = cy + motion.y;
      if (haveHistory_ && px >= 0.0f && py >= 0.0f && px <= static_cast<float>(W) && py <= static_cast<float>(H)) {
        const float fx = px - 0.5f, fy = py - 0.5f;
        const int x1 = static_cast<int>(std::floor(fx)), y1 = static_cast<int>(std::floor(fy));
        const bool inside = x1 >= 1 && y1 >= 1 && x1 + 2 < int(W) && y1 + 2 < int(H);   // no clamping needed
        const size_t at = size_t(y1) * W + size_t(x1);
        const size_t taps[4] = {inside ? at : historyIndex(x1, y1), inside ? at + 1 : historyIndex(x1 + 1, y1),
                                inside ? at + W : historyIndex(x1, y1 + 1),
                                inside ? at + W + 1 : historyIndex(x1 + 1, y1 + 1)};
        bool seen = false;
        for (const size_t t : taps) seen = seen || instance_[t] == surface;
        if (seen) {
          const float tx = fx - static_cast<float>(x1), ty = fy - static_cast<float>(y1);
          const std::array<float, 4> wx = catmullRom(tx), wy = catmullRom(ty);
          std::array<size_t, 4> columns, rows;
          for (int i = 0; i < 4; ++i) {
            columns[size_t(i)] = inside ? size_t(x1 - 1 + i) : size_t(std::clamp(x1 - 1 + i, 0, int(W) - 1));
            rows[size_t(i)] = (inside ? size_t(y1 - 1 + i) : size_t(std::clamp(y1 - 1 + i, 0, int(H) - 1))) * W;
          }
          // Four-wide: one load and one multiply-add per tap.
          Lanes sum4 = {0.0f, 0.0f, 0.0f, 0.0f};
          for (size_t j = 0; j < 4; ++j) {
            const glm::vec4* row = &history_[rows[j]];
            const Lanes r = load(row[columns[0]]) * wx[0] + load(row[columns[1]]) * wx[1] +
                            load(row[columns[2]]) * wx[2] + load(row[columns[3]]) * wx[3];
            sum4 += r * wy[j];
          }
          // Anti-ringing: within the four nearest taps' range.
          Lanes lo = load(history_[taps[0]]), hi = lo;
          for (size_t t = 1; t < 4; ++t) {
            const Lanes v = load(history_[taps[t]]);
            lo = lo < v ? lo : v;
            hi = hi > v ? hi : v;
          }
          sum4 = sum4 < lo ? lo : sum4;
          sum4 = sum4 > hi ? hi : sum4;
          glm::vec3 history(sum4[0], sum4[1], sum4[2]);
          const float cap = weightCap_ * (config_.movingMemory + (1.0f - config_.movingMemory) * still);
          const float historyWeight =
              std::min(cap, (1 - ty) * ((1 - tx) * weight_[taps[0]] + tx * weight_[taps[1]]) +
                                ty * ((1 - tx) * weight_[taps[2]] + tx * weight_[taps[3]]));
          // Variance clipping toward the neighbourhood mean, wider for a still pixel.
          glm::vec3 boxLo = mean - gamma * sigma, boxHi = mean + gamma * sigma;
          // A still pixel keeps what last frame's samples showed too: a line thinner than a
          // traced pixel, missed by this frame's samples, is not clipped away. Not where this
          // frame's mean left last frame's box: the light changed (a muzzle flash on the weapon).
          const size_t previous = historyIndex(static_cast<int>(std::floor(px)), static_cast<int>(std::floor(py)));
          const bool sameLight = glm::all(glm::greaterThanEqual(mean, boxLo_[previous])) &&
                                 glm::all(glm::lessThanEqual(mean, boxHi_[previous]));
          const float keepLast = sameLight ? still : 0.0f;
          boxLo = glm::min(boxLo, glm::mix(boxLo, boxLo_[previous], keepLast));
          boxHi = glm::max(boxHi, glm::mix(boxHi, boxHi_[previous], keepLast));
          const glm::vec3 centre = 0.5f * (boxLo + boxHi);
          const glm::vec3 extent = 0.5f * (boxHi - boxLo) + glm::vec3(1e-3f);
          const glm::vec3 offset = history - centre;
          const glm::vec3 units = glm::abs(offset) / extent;
          const float worst = std::max(units.x, std::max(units.y, units.z));
          if (worst > 1.0f) history = centre + offset / worst;
          const float total = historyWeight + confidence;
          const float alpha = total > 0.0f ? confidence / total : 1.0f;
          result = history + alpha * (current - history);
          weight = total;
          historyUsed = true;
        }
      }
      // Without a history, the traced frame interpolated bilinearly (as the stretch shows it):
      // this frame's samples within the kernel alone are one sample or none per output pixel.
      if (!historyUsed) result = bilinearSample(frame, qx - frame.jitter.x - 0.5f, qy - frame.jitter.y - 0.5f);
      const size_t o = size_t{oy} * W + ox;
      nextHistory_[o] = glm::vec4(result, 0.0f);
      nextWeight_[o] = weight;
      nextInstance_[o] = surface;
      nextBoxLo_[o] = mean - gamma * sigma;
      nextBoxHi_[o] = mean + gamma * sigma;
      const glm::vec3 rgb = fromYCoCg(result);
      output_[o * 4 + 0] = encode(rgb.r);
      output_[o * 4 + 1] = encode(rgb.g);
      output_[o * 4 + 2] = encode(rgb.b);
      output_[o * 4 + 3] = 255;
    }
  }
}

}  // namespace pa::taau::test
