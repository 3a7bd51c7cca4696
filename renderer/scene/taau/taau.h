#pragma once
// Temporal anti-aliasing and upscaling (TAAU): each traced frame, sampled at a sub-pixel jitter
// that changes from frame to frame, is merged into a history kept at the output resolution.
// Per output pixel: this frame's samples within 0.7 output pixels (1.5 for a moving pixel) are
// weighed by a smooth kernel (their weight sum is this frame's confidence); the history is
// fetched at the pixel's previous position (the traced motion vectors, or the camera's rotation
// for the sky) by a Catmull-Rom filter clamped to its four nearest taps (sharp, no ringing),
// clipped to the 3 x 3 traced neighbourhood's colour box in YCoCg (variance clipping), and
// dropped where the surface is new (no motion, or none of the taps showed the same instance;
// such a pixel shows the frame interpolated bilinearly). The blend is a running weighted mean of
// confidence with a capped memory (shorter for a moving pixel), so a still view converges to the
// image supersampled with that kernel at the output resolution.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "renderer/scene/integrator/camera_rays.h"
#include "renderer/scene/scene_types.h"

namespace pa::taau {

/// Frames in one cycle of the jitter sequence.
inline constexpr uint32_t kJitterPeriod = 16;

/// Sub-pixel offset of frame `frame`'s samples from their pixel centres, in traced pixels, each
/// component in (-0.5, 0.5): Halton bases 2 and 3, repeating every kJitterPeriod frames.
glm::vec2 jitter(uint32_t frame);

/// Tuning of the resolve.
struct Config {
  float kernelRadius = 0.7f;     ///< Reach of a sample's weight, in output pixels...
  float movingKernelRadius = 1.5f;   ///< ... for a pixel moving by half an output pixel or more,
  /// or this many traced pixels where that is wider (below a scale of 0.5, where 1.5 output pixels
  /// leave some output pixels without a sample within reach: a grid of samples showed on moving
  /// surfaces at 0.35).
  float movingKernelReach = 0.75f;
  float memoryFrames = 16.0f;    ///< Cap on the history's weight, in frames of average confidence...
  /// ... times this for a pixel moving by an output pixel or more (from 1 when still): each
  /// frame's resampling of a moving history blurs it, and a short memory also follows changed
  /// lighting sooner (demo088-test1: 30.5 dB against scale 1 with 1, 31.3 dB with 0.1).
  float movingMemory = 0.1f;
  /// Colour-box half-size in standard deviations for a still pixel (whose box also takes in the
  /// previous frame's)...
  float clipStill = 2.5f;
  float clipMoving = 1.0f;       ///< ... and for one moving by an output pixel or more.
};

/// One traced frame (width * height each, row-major from the top row).
struct Frame {
  uint32_t width = 0;
  uint32_t height = 0;
  std::span<const uint8_t> rgba8;        ///< Display colours (sRGB encoded), alpha ignored.
  /// Previous film position minus this sample's, in traced pixels; NaN where unknown (sky,
  /// portals, new instances, first frame).
  std::span<const glm::vec2> motion;
  std::span<const float> depth;          ///< First-hit distance (+inf: sky).
  std::span<const InstanceId> instance;  ///< First-hit instance (kNoId: none).
  glm::vec2 jitter{0.0f};                ///< Where this frame's samples lie relative to their pixel centres.
  /// This frame's camera; with it, the sky (infinite depth, no motion) is reprojected by the
  /// camera's rotation since the previous frame. Null: sky pixels count as new every frame.
  const Camera* camera = nullptr;
};

/// The traced samples within the kernel's reach along one axis of an output pixel.
struct AxisTaps {
  int first = 0;         ///< First traced index within reach.
  int count = 0;         ///< Traced indices within reach (from first on).
  int nearest = 0;       ///< The traced index nearest to the output pixel's centre.
  uint32_t offset = 0;   ///< Into the axis' squared distances (output pixels), one per index.
};

/// Fills `taps` (one per output index of `out`) and their squared distances (in output pixels,
/// into `d2`, whose memory is kept) for one axis of a frame traced at `traced` with this jitter,
/// for a kernel of `radius` output pixels.
void kernelTaps(uint32_t traced, uint32_t out, float jitter, float radius, std::vector<AxisTaps>& taps,
                std::vector<float>& d2);

/// The moving kernel's radius in output pixels for a frame traced at tracedWidth x tracedHeight
/// and resolved to outWidth x outHeight: config.movingKernelRadius, or config.movingKernelReach
/// traced pixels where that is wider.
float movingKernelRadius(const Config& config, uint32_t tracedWidth, uint32_t tracedHeight, uint32_t outWidth,
                         uint32_t outHeight);

/// The most history weight a pixel keeps (confidence units): config.memoryFrames frames of the
/// kernel's average confidence, its integral (1 - r^2/R^2)^2 over the disc (pi R^2 / 3) times the
/// traced samples per output pixel.
float historyWeightCap(const Config& config, float samplesPerPixel);

/// The TAAU resolve and its history. Not thread-safe; its rows run in parallel on the calling
/// thread's task arena, and the result does not depend on the thread count. Each row is resolved
/// lanes::kCount output pixels a step over planar arrays (README.md "Lanes").
class Upscaler {
 public:
  /// An upscaler with the given tuning.
  explicit Upscaler(const Config& config = {});

  /// Merges `frame` into the history at outWidth x outHeight and returns the output image
  /// (RGBA8, sRGB, alpha 255), valid until the next call. A new output size starts again.
  std::span<const uint8_t> resolve(const Frame& frame, uint32_t outWidth, uint32_t outHeight);

  /// Forgets the history (the next frame starts from its own samples).
  void reset();

  /// Per output pixel, the history's weight after the last resolve (confidence units).
  std::span<const float> historyWeight() const {
    return std::span<const float>(weight_).first(size_t{outWidth_} * outHeight_);
  }

 private:
  /// One radius' column taps laid out for a step of lanes::kCount output columns (8 with AVX, 4
  /// without): every column takes `count` taps (those past its own count at a squared distance
  /// beyond the kernel), tap b of column x at [b * paddedWidth_ + x]; a tap's traced column is
  /// `base` of its block of columns plus its offset; `kind`: how the block's taps are read (a
  /// Fetch::Kind in taau.cpp: offsets below kCount or 2 kCount are permutations of one or two loads).
  struct LaneTaps {
    int count = 0;
    std::vector<int32_t> offset;
    std::vector<float> d2;
    std::vector<int32_t> base;     ///< Per block of kCount columns.
    std::vector<uint8_t> kind;     ///< Per block of kCount columns.
  };
  /// Three planes (Y, Co, Cg), each padded so 16 values can be read from any of its indices.
  struct Planes {
    std::vector<float> y, co, cg;
    void assign(size_t n) {
      y.assign(n + kPad, 0.0f);
      co.assign(n + kPad, 0.0f);
      cg.assign(n + kPad, 0.0f);
    }
    void swap(Planes& o) {
      y.swap(o.y);
      co.swap(o.co);
      cg.swap(o.cg);
    }
  };
  /// Lays one radius' column taps out for kCount output columns a step.
  void laneTaps(uint32_t traced, const std::vector<AxisTaps>& taps, const std::vector<float>& d2, LaneTaps& lanes) const;
  void prepareRows(const Frame& frame, uint32_t y0, uint32_t y1);
  void neighbourhoodRows(const Frame& frame, uint32_t y0, uint32_t y1);
  void resolveRows(const Frame& frame, uint32_t y0, uint32_t y1);

  static constexpr uint32_t kEncodeSteps = 4096;   ///< sqrt(linear) steps of the encoding table.
  static constexpr size_t kPad = 16;   ///< Readable values past each plane's end (>= 2 lanes::kCount).

  Config config_;
  uint32_t outWidth_ = 0, outHeight_ = 0;
  uint32_t paddedWidth_ = 0;   ///< outWidth_ rounded up to lanes::kCount.
  bool haveHistory_ = false;
  std::optional<Camera> lastCamera_;
  std::optional<CameraRays> rays_, previousRays_;   ///< This frame's and the last one's, output size.
  float weightCap_ = 1.0f;
  Planes samples_;                 ///< This frame, linear YCoCg, traced size.
  /// Per traced pixel, its 3 x 3 neighbourhood: colour mean and deviation (YCoCg), and the depth,
  /// instance and motion of the closest sample.
  Planes mean_, sigma_;
  std::vector<float> closestDepth_, closestMotionX_, closestMotionY_;
  std::vector<int32_t> closestInstance_;
  Planes history_, nextHistory_;   ///< Linear YCoCg, output size.
  std::vector<float> weight_, nextWeight_;
  std::vector<int32_t> instance_, nextInstance_;
  Planes boxLo_, boxHi_, nextBoxLo_, nextBoxHi_;   ///< Each frame's clip box, output size.
  std::vector<uint8_t> output_;
  std::vector<AxisTaps> columns_, rows_;        ///< This frame's kernel taps per output column and row.
  std::vector<float> columnD2_, rowD2_;
  std::vector<AxisTaps> movingColumns_, movingRows_;   ///< The same for movingKernelRadius.
  std::vector<float> movingColumnD2_, movingRowD2_;
  float movingRadius_ = 1.5f;   ///< This frame's moving kernel radius, output pixels.
  LaneTaps laneColumns_, movingLaneColumns_;           ///< columns_ and movingColumns_, kCount columns a step.
  std::vector<int32_t> nearestColumn_;                 ///< Per output column (paddedWidth_).
  std::array<float, 256> decode_{};              ///< sRGB byte -> linear.
  std::array<uint8_t, kEncodeSteps> encode_{};   ///< sqrt(linear) -> sRGB byte.
};

}  // namespace pa::taau
