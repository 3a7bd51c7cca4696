#pragma once
// Edge-avoiding à-trous wavelet denoiser (Dammertz et al. 2010) with the variance-guided
// luminance weight of SVGF (Schied et al. 2017, spatial part only). It filters the
// demodulated radiance (radiance / first-hit albedo) with edge-stopping weights from the
// first-hit normal, a screen-space depth gradient and luminance, then remodulates. Pixels
// without geometry (sky, depth = inf) or with black albedo are left as they are.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace pa::denoise {

/// Filter strength. The defaults are those of SVGF, tuned on OpenArena maps at 1 spp.
struct Config {
  uint32_t iterations = 5;        ///< À-trous passes with steps 1, 2, 4, ...; 0 = identity.
  float sigmaNormal = 128.0f;     ///< Exponent on max(0, dot(n_p, n_q)): higher = sharper at creases.
  float sigmaDepth = 1.0f;        ///< Depth tolerance in units of the depth change the gradient predicts.
  float sigmaLuminance = 4.0f;    ///< Luminance tolerance in standard deviations of the pixel's noise.
};

/// Per-pixel guide images (width * height each, row-major from the top row), as the film
/// resolves them: mean first-hit albedo, normal and distance (inf = nothing hit) and the
/// variance of each pixel's mean luminance.
struct Guides {
  uint32_t width = 0;
  uint32_t height = 0;
  std::span<const glm::vec3> albedo;
  std::span<const glm::vec3> normal;
  std::span<const float> depth;
  std::span<const float> variance;
  uint64_t samplesPerPixel = 1;   ///< Samples in each mean: below 4 the noise is estimated spatially.
};

/// The filter and its scratch buffers (reused across frames of the same size).
class Denoiser {
 public:
  /// A denoiser with the given strength (values are clamped to sane ranges).
  explicit Denoiser(const Config& config = {});
  /// The strength in use.
  const Config& config() const { return config_; }
  /// Filters `radiance` (width * height) in place. Non-finite radiance never spreads: such a
  /// pixel takes its neighbours' estimate (0 when it has none, or when it has no geometry).
  /// Parallel over rows with tbb::parallel_for in the calling task arena; the result does not
  /// depend on the thread count. Throws std::invalid_argument when a buffer size mismatches.
  void apply(const Guides& guides, std::span<glm::vec3> radiance);

  /// How a pixel takes part in the filter.
  enum class Role : uint8_t {
    Filtered,      ///< Filtered and a neighbour of others.
    Hole,          ///< Geometry but non-finite radiance: filtered from neighbours, never used by them.
    PassThrough,   ///< No geometry or black albedo: left as it is.
  };
  /// Per-pixel edge-stopping data.
  struct PixelGuide {
    glm::vec3 normal{0.0f};
    float depth = 0.0f;
    float depthDx = 0.0f;   ///< Change of depth per pixel along x (one-sided, smaller side).
    float depthDy = 0.0f;
    Role role = Role::PassThrough;
  };

 private:
  void prepareRows(const Guides& guides, std::span<const glm::vec3> radiance, uint32_t y0, uint32_t y1);
  void estimateVarianceRows(uint32_t width, uint32_t height, uint32_t y0, uint32_t y1);
  void filterRows(uint32_t width, uint32_t height, uint32_t step, uint32_t y0, uint32_t y1);

  Config config_;
  std::vector<PixelGuide> guide_;
  std::vector<glm::vec4> current_, next_;   // demodulated rgb + luminance variance in w
};

}  // namespace pa::denoise
