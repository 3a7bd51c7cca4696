#include "port/engine_glue/dynamic_resolution.h"

#include <algorithm>
#include <cmath>

namespace glue {

float ResolutionController::update(double frameMs, float targetFps, float minScale) {
  const float lo = std::clamp(std::isfinite(minScale) ? minScale : 1.0f, 0.1f, 1.0f);
  if (!(targetFps > 0.0f) || !std::isfinite(targetFps)) {
    scale_ = 1.0f;
    sumMs_ = 0.0;
    frames_ = 0;
    return scale_;
  }
  scale_ = std::clamp(scale_, lo, 1.0f);
  if (!(frameMs > 0.0) || !std::isfinite(frameMs)) return scale_;
  sumMs_ += frameMs;
  if (++frames_ < kSettleFrames) return scale_;
  const double measured = sumMs_ / frames_;
  sumMs_ = 0.0;
  frames_ = 0;
  const double target = 1000.0 / targetFps;
  if (std::fabs(measured - target) <= kDeadBand * target) return scale_;
  // Cost ~ pixels ~ scale^2; half the step (the fixed part of a frame does not scale).
  const double wanted = scale_ * std::sqrt(target / measured);
  const double damped = scale_ + 0.5 * (wanted - scale_);
  float next = static_cast<float>(std::round(damped * 32.0) / 32.0);
  if (next == scale_) next = scale_ + (wanted > scale_ ? 1.0f : -1.0f) / 32.0f;   // always move at least one step
  scale_ = std::clamp(next, lo, 1.0f);
  return scale_;
}

}  // namespace glue
