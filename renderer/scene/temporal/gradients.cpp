#include "renderer/scene/temporal/gradients.h"

#include <algorithm>
#include <limits>

#include "renderer/scene/sampling/sobol_sampler.h"

namespace pa::temporal {

namespace {

GradientConfig clamped(GradientConfig c) {
  c.stratum = std::clamp(c.stratum, 2u, 16u);
  c.filterRadius = std::min(c.filterRadius, 4u);
  c.gain = std::isfinite(c.gain) ? std::clamp(c.gain, 0.0f, 100.0f) : 1.0f;
  return c;
}

}  // namespace

GradientEstimator::GradientEstimator(const GradientConfig& config) : config_(clamped(config)) {}

void GradientEstimator::configure(const GradientConfig& config) {
  const GradientConfig next = clamped(config);
  if (next.stratum == config_.stratum && next.filterRadius == config_.filterRadius && next.gain == config_.gain) return;
  config_ = next;
  width_ = height_ = 0;   // the next beginFrame() sizes the strata again
  havePrevious_ = resolved_ = false;
}

void GradientEstimator::reset() {
  havePrevious_ = false;
  resolved_ = false;
}

void GradientEstimator::beginFrame(uint32_t width, uint32_t height) {
  if (width != width_ || height != height_) {
    width_ = width;
    height_ = height;
    havePrevious_ = false;
    const size_t n = size_t{width} * height;
    const float none = std::numeric_limits<float>::quiet_NaN();
    current_.assign(n, none);
    previous_.assign(n, none);
    drop_.assign(n, 0.0f);
    strataX_ = (width + config_.stratum - 1) / config_.stratum;
    strataY_ = (height + config_.stratum - 1) / config_.stratum;
    const size_t strata = size_t{strataX_} * strataY_;
    targets_.assign(strata, GradientTarget{});
    difference_.assign(strata, 0.0f);
    magnitude_.assign(strata, 0.0f);
    strataDrop_.assign(strata, 0.0f);
  }
  resolved_ = false;   // plan() sets every target
  std::fill(difference_.begin(), difference_.end(), 0.0f);
  std::fill(magnitude_.begin(), magnitude_.end(), 0.0f);
}

void GradientEstimator::pickPixel(uint32_t sx, uint32_t sy, uint32_t frameSeed, uint32_t& x, uint32_t& y) const {
  const uint32_t x0 = sx * config_.stratum, y0 = sy * config_.stratum;
  const uint32_t w = std::min(config_.stratum, width_ - x0), h = std::min(config_.stratum, height_ - y0);
  const uint32_t pick = sampling::hashCombine(frameSeed, sy * strataX_ + sx) % (w * h);
  x = x0 + pick % w;
  y = y0 + pick / w;
}

void GradientEstimator::record(size_t k, float luminance) {
  const GradientTarget& t = targets_[k];
  if (!t.valid) return;
  const float then = previous_[size_t{t.y} * width_ + t.x];
  if (!std::isfinite(luminance) || !std::isfinite(then)) return;
  difference_[k] = std::abs(luminance - then);
  magnitude_[k] = std::max(std::max(luminance, then), 0.0f);
}

void GradientEstimator::resolve() {
  const int radius = static_cast<int>(config_.filterRadius);
  const int sxCount = static_cast<int>(strataX_), syCount = static_cast<int>(strataY_);
  for (int sy = 0; sy < syCount; ++sy) {
    for (int sx = 0; sx < sxCount; ++sx) {
      // Pooled: one re-traced sample says little on its own (a lamp chosen on the other side of a
      // changed choice), its neighbours' agree where the light really changed.
      double difference = 0.0, magnitude = 0.0;
      for (int dy = std::max(0, sy - radius); dy <= std::min(syCount - 1, sy + radius); ++dy)
        for (int dx = std::max(0, sx - radius); dx <= std::min(sxCount - 1, sx + radius); ++dx) {
          const size_t k = size_t(dy) * strataX_ + size_t(dx);
          difference += difference_[k];
          magnitude += magnitude_[k];
        }
      const double share = magnitude > 0.0 ? config_.gain * difference / magnitude : 0.0;
      strataDrop_[size_t(sy) * strataX_ + size_t(sx)] = static_cast<float>(std::clamp(share, 0.0, 1.0));
    }
  }
  for (uint32_t y = 0; y < height_; ++y) {
    const float* row = strataDrop_.data() + size_t{y / config_.stratum} * strataX_;
    float* out = drop_.data() + size_t{y} * width_;
    for (uint32_t x = 0; x < width_; ++x) out[x] = row[x / config_.stratum];
  }
  resolved_ = true;
}

void GradientEstimator::endFrame() {
  std::swap(current_, previous_);
  havePrevious_ = width_ > 0 && height_ > 0;
}

}  // namespace pa::temporal
