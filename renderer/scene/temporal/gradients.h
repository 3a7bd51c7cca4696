#pragma once
// Temporal gradients in the manner of A-SVGF (Schied, Peters and Dachsbacher 2018, "Gradient
// Estimation for Real-Time Adaptive Temporal Filtering"): where the lighting changed since the last
// frame, the temporal stage should forget its history at once, and keep it everywhere else.
//
// The image is cut into strata of GradientConfig::stratum x stratum pixels. In each, one pixel
// (a different one each frame) is followed back through its motion vector to last frame's pixel,
// and last frame's first sample of that pixel is traced again: the same camera ray, the same
// random numbers, this frame's scene. Where nothing changed it gives last frame's value bit for
// bit, so the difference is 0 however noisy the picture is; where a light went out, moved or
// appeared, or an occluder moved, it differs by what changed. Per stratum, the differences and
// the larger of the two values are summed over the (2 filterRadius + 1)^2 strata around it, and
// their ratio times GradientConfig::gain (at most 1) is the share of history the temporal stage
// drops there (historyDrop()).
//
// Backward, not forward as in the paper: the re-traced sample is one of last frame's, found
// from this frame's pixel, so no sample of this frame is replaced and no forward-projection pass
// is needed; the extra cost is one sample per stratum. The renderer does the tracing (the
// temporal stage knows nothing of the integrator): plan(), then record() per target, then
// resolve().
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "renderer/scene/temporal/motion.h"

namespace pa::temporal {

/// Gradient sampling parameters.
struct GradientConfig {
  /// Side of the pixel blocks that get one re-traced sample each (2..16). Along four demos 3, 4, 6
  /// and 8 gave the same error within 0.6% (docs/performance.md); 6 costs one sample in 36.
  uint32_t stratum = 6;
  uint32_t filterRadius = 1;   ///< Strata on each side pooled into a stratum's gradient (0..4).
  /// The share of history dropped per unit of relative change (A-SVGF's is 1). With 1, a light
  /// dimmed to a third leaves two thirds of the old light in the next frame's blend at alpha 0.1
  /// (the history keeps 1 - 2/3 of its weight); with 2 any change by half or more drops it all.
  float gain = 2.0f;
};

/// Last frame's pixel whose first sample a stratum traces again (valid false: none this frame).
struct GradientTarget {
  uint32_t x = 0, y = 0;
  bool valid = false;
};

/// Per-stratum gradients between this frame's scene and last frame's samples. One per view.
class GradientEstimator {
 public:
  /// An estimator with the given parameters and no samples.
  explicit GradientEstimator(const GradientConfig& config = {});
  /// The parameters in use (clamped to their ranges).
  const GradientConfig& config() const { return config_; }
  /// Takes new parameters; when they differ from those in use, forgets last frame's samples.
  void configure(const GradientConfig& config);
  /// Forgets last frame's samples: the next frame has no gradients.
  void reset();
  /// Starts a frame of width x height. Last frame's samples stay only if the size is the same.
  void beginFrame(uint32_t width, uint32_t height);
  /// This frame's plane of first-sample luminance (width * height, row-major from the top): the
  /// renderer writes each pixel's lit luminance (radiance - emission) there, NaN where not finite.
  std::span<float> sampleLuminance() { return current_; }
  /// True when last frame's samples are there to compare with.
  bool havePrevious() const { return havePrevious_; }

  /// Chooses each stratum's pixel from `frameSeed` and follows it back through the G-buffer's
  /// motion: jitterOf(x, y) is the film offset (0..1) of this frame's first sample of pixel (x, y).
  template <class JitterOf>
  void plan(const GBuffer& gbuffer, uint32_t frameSeed, JitterOf&& jitterOf);
  /// The targets plan() chose, one per stratum (row-major over strata).
  std::span<const GradientTarget> targets() const { return targets_; }
  /// The lit luminance of target k's sample traced again in this frame's scene.
  void record(size_t k, float luminance);
  /// Pools the differences and fills historyDrop(). Without last frame's samples it is all 0.
  void resolve();
  /// Per pixel, after resolve() in this frame: the share (0..1) of its history the temporal
  /// stage drops; empty before.
  std::span<const float> historyDrop() const { return resolved_ ? std::span<const float>(drop_) : std::span<const float>(); }
  /// Per stratum, after resolve(): its pooled gradient (the same values historyDrop() spreads).
  std::span<const float> strataDrop() const { return strataDrop_; }
  /// Strata across and down.
  uint32_t strataX() const { return strataX_; }
  uint32_t strataY() const { return strataY_; }
  /// Ends the frame: this frame's luminance becomes last frame's.
  void endFrame();

 private:
  /// The pixel of stratum (sx, sy) chosen for `frameSeed` (inside the image).
  void pickPixel(uint32_t sx, uint32_t sy, uint32_t frameSeed, uint32_t& x, uint32_t& y) const;

  GradientConfig config_;
  uint32_t width_ = 0, height_ = 0, strataX_ = 0, strataY_ = 0;
  bool havePrevious_ = false;
  bool resolved_ = false;   // resolve() ran in this frame
  std::vector<float> current_, previous_;   // first-sample lit luminance, this and last frame
  std::vector<GradientTarget> targets_;
  std::vector<float> difference_, magnitude_;   // per stratum: |now - then|, max(now, then)
  std::vector<float> strataDrop_, drop_;
};

template <class JitterOf>
void GradientEstimator::plan(const GBuffer& gbuffer, uint32_t frameSeed, JitterOf&& jitterOf) {
  for (uint32_t sy = 0; sy < strataY_; ++sy) {
    for (uint32_t sx = 0; sx < strataX_; ++sx) {
      GradientTarget& t = targets_[size_t{sy} * strataX_ + sx];
      t = GradientTarget{};
      if (!havePrevious_ || gbuffer.width != width_ || gbuffer.height != height_) continue;
      uint32_t x, y;
      pickPixel(sx, sy, frameSeed, x, y);
      const glm::vec2 m = gbuffer.motion[size_t{y} * width_ + x];
      if (!std::isfinite(m.x) || !std::isfinite(m.y)) continue;   // sky, portal view, new instance
      const glm::vec2 jitter = jitterOf(x, y);
      const float px = static_cast<float>(x) + jitter.x + m.x, py = static_cast<float>(y) + jitter.y + m.y;
      if (!(px >= 0.0f && py >= 0.0f && px < static_cast<float>(width_) && py < static_cast<float>(height_))) continue;
      t.x = static_cast<uint32_t>(px);
      t.y = static_cast<uint32_t>(py);
      t.valid = std::isfinite(previous_[size_t{t.y} * width_ + t.x]);
    }
  }
}

}  // namespace pa::temporal
