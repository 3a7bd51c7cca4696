#pragma once
// The scalar TAAU resolve (one output pixel at a time, interleaved YCoCg): the reference the lane
// resolve (taau.cpp) is tested against.
#include "renderer/scene/taau/taau.h"

namespace pa::taau::test {

/// The one-pixel-at-a-time resolve that taau::Upscaler replaced, kept as the reference its output
/// is compared with (same interface).
class ScalarUpscaler {
 public:
  /// An upscaler with the given tuning.
  explicit ScalarUpscaler(const Config& config = {});

  /// Merges `frame` into the history at outWidth x outHeight and returns the output image
  /// (RGBA8, sRGB, alpha 255), valid until the next call. A new output size starts again.
  std::span<const uint8_t> resolve(const Frame& frame, uint32_t outWidth, uint32_t outHeight);

  /// Forgets the history (the next frame starts from its own samples).
  void reset();

  /// Per output pixel, the history's weight after the last resolve (confidence units).
  std::span<const float> historyWeight() const { return weight_; }

 private:
  void prepareRows(const Frame& frame, uint32_t y0, uint32_t y1);
  void neighbourhoodRows(const Frame& frame, uint32_t y0, uint32_t y1);
  void resolveRows(const Frame& frame, uint32_t y0, uint32_t y1);
  uint8_t encode(float linear) const;
  /// This frame's colour (linear YCoCg) interpolated bilinearly at traced-pixel position (fx, fy)
  /// (pixel centres at +0.5), clamped to the frame.
  glm::vec3 bilinearSample(const Frame& frame, float fx, float fy) const;

  static constexpr uint32_t kEncodeSteps = 4096;   ///< sqrt(linear) steps of the encoding table.

  Config config_;
  uint32_t outWidth_ = 0, outHeight_ = 0;
  bool haveHistory_ = false;
  std::optional<Camera> lastCamera_;
  std::optional<CameraRays> rays_, previousRays_;   ///< This frame's and the last one's, output size.
  float weightCap_ = 1.0f;
  /// A traced pixel's 3 x 3 neighbourhood: colour mean and deviation (YCoCg), closest sample.
  struct Neighbourhood {
    glm::vec3 mean;
    glm::vec3 sigma;
    uint32_t closest;
  };
  std::vector<glm::vec3> samples_;           ///< This frame, linear YCoCg, traced size.
  std::vector<Neighbourhood> neighbourhood_;   ///< Per traced pixel.
  std::vector<glm::vec4> history_, nextHistory_;   ///< Linear YCoCg (w unused), output size.
  std::vector<float> weight_, nextWeight_;
  std::vector<InstanceId> instance_, nextInstance_;
  std::vector<glm::vec3> boxLo_, boxHi_, nextBoxLo_, nextBoxHi_;   ///< Each frame's clip box, output size.
  std::vector<uint8_t> output_;
  std::vector<AxisTaps> columns_, rows_;        ///< This frame's kernel taps per output column and row.
  std::vector<float> columnD2_, rowD2_;
  std::vector<AxisTaps> movingColumns_, movingRows_;   ///< The same for movingKernelRadius.
  std::vector<float> movingColumnD2_, movingRowD2_;
  float movingRadius_ = 1.5f;   ///< This frame's moving kernel radius, output pixels.
  std::array<float, 256> decode_{};              ///< sRGB byte -> linear.
  std::array<uint8_t, kEncodeSteps> encode_{};   ///< sqrt(linear) -> sRGB byte.
};

}  // namespace pa::taau::test
