#pragma once
// Edge-avoiding à-trous wavelet denoiser (Dammertz et al. 2010) with the variance-guided
// luminance weight of SVGF (Schied et al. 2017, spatial part only). It filters the
// demodulated radiance ((radiance - emission) / first-hit albedo: what the camera sees of
// emitters is exact and stays unfiltered) with edge-stopping weights from the first-hit normal,
// a screen-space depth gradient and luminance, then remodulates and adds the emission back. Pixels
// without geometry (sky, depth = inf) or with black albedo are left as they are. The kernel is
// the 3 x 3 B-spline (1, 2, 1) / 4 of the real-time variants (9 taps per pass, not 25).
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <tbb/enumerable_thread_specific.h>

namespace pa::denoise {

/// Filter strength. The sigmas are SVGF's defaults; 5 passes reach 65 x 65 pixels.
struct Config {
  uint32_t iterations = 5;        ///< 3 x 3 à-trous passes with steps 1, 2, 4, ... (at most 10); 0 = identity.
  float sigmaNormal = 128.0f;     ///< Normal weight e^(sigma (dot(n_p, n_q) - 1)) ~ dot^sigma: higher = sharper creases.
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
  /// Mean radiance gathered before the first scattering (Film::emission()): left out of the
  /// filter and added back unchanged. Empty = none (everything is filtered).
  std::span<const glm::vec3> emission;
  /// Frames in each pixel's temporal history (temporal::TemporalFilter), or empty: when set,
  /// pixels with 4 or more frames take `variance` as their noise and the others a spatial
  /// estimate (SVGF), whatever samplesPerPixel says.
  std::span<const float> historyLength;
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
  /// As apply(), and writes each filtered pixel's demodulated colour after the first pass into
  /// `firstPass` (width * height; other pixels are left as they are): SVGF's temporal feedback.
  void apply(const Guides& guides, std::span<glm::vec3> radiance, std::span<glm::vec3> firstPass);

 private:
  /// One float image with a border of `pad` zeros on every side, so that taps need no bounds
  /// checks: row(y)[x] for x in [-pad, width + pad).
  struct Plane {
    std::vector<float> data;
    size_t stride = 0;
    size_t pad = 0;
    float* row(int y) { return data.data() + static_cast<size_t>(y + static_cast<int>(pad)) * stride + pad; }
  };
  /// The filtered signal: demodulated colour and the variance of its luminance.
  struct Signal {
    Plane red, green, blue, variance;
  };

  /// Per-row sums of one task (no allocation per pixel).
  struct RowScratch {
    std::vector<float> red, green, blue, weight, variance;
    RowScratch& sized(uint32_t width);   ///< Sizes every array to `width` rounded up to whole lanes.
  };

  void resize(uint32_t width, uint32_t height);
  void prepareRows(const Guides& guides, std::span<const glm::vec3> radiance, uint32_t y0, uint32_t y1);
  /// prepareRows() for the kCount pixels of row y from x on (interior: x > 0, x + kCount < width).
  void prepareLanes(const Guides& guides, std::span<const glm::vec3> radiance, uint32_t x, uint32_t y);
  void estimateVarianceRows(uint32_t y0, uint32_t y1);
  void filterRows(uint32_t step, uint32_t y0, uint32_t y1);

  Config config_;
  uint32_t width_ = 0, height_ = 0, pad_ = 0;
  // Guides, padded: unit normal, depth, its per-pixel slopes, and two masks: `gives` = 1 where a
  // pixel is a valid neighbour, `takes` = 1 where a pixel is filtered (valid or a hole).
  // `ownVariance` = 1 where the pixel's variance comes from the guides, not the spatial estimate.
  Plane normalX_, normalY_, normalZ_, depth_, depthDx_, depthDy_, gives_, takes_, ownVariance_;
  Signal current_, next_;
  /// Each worker thread's row scratch, kept between frames (no allocation in steady state).
  tbb::enumerable_thread_specific<RowScratch> rowScratch_;
};

}  // namespace pa::denoise
