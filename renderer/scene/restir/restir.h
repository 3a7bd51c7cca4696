#pragma once
// Spatiotemporal reservoir resampling of direct light (ReSTIR DI, Bitterli et al. 2020) at each
// pixel's first camera-visible diffuse or glossy hit, for the Direct and Path integrators. Per
// frame, before the pixels are traced: (1) each pixel resamples `candidates` light samples drawn
// by the LightSampler (resampled importance sampling, target = unshadowed luminance of
// BSDF x radiance at the hit, over each light's own measure: LightPoint) into a reservoir and
// traces one shadow ray to the one it kept (W = 0 when occluded); (2) combines it with last
// frame's final reservoir at the pixel's previous position (motion of the G-buffer; rejected
// unless instance, material, depth and normal match; M capped); (3) combines that with a few
// neighbours' reservoirs. Combinations weight by 1/Z: Z sums the M of the inputs that could have
// produced the sample kept (its target there > 0 and it is visible from there, one shadow ray per
// input), which keeps the estimate unbiased where the inputs' supports differ (README.md). The
// integrator then shades the hit with the final reservoir's sample and weight instead of its own
// light sample, and gives BSDF-sampled hits of lights the sampler could pick weight 0 there.
// Every step is per pixel and reads only the previous step's buffers: the result does not depend
// on the thread count.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/scene/integrator/camera_rays.h"
#include "renderer/scene/lights/light_sampler.h"
#include "renderer/scene/scene_types.h"
#include "renderer/scene/temporal/motion.h"
#include "renderer/scene/world/render_scene.h"

namespace pa::restir {

/// Knobs of the resampling.
/// Defaults measured on oa_dm3 at 320 x 180 with the temporal stage and the denoiser after it
/// (docs/performance.md, "Light selection"): more candidates cost time and gained nothing once
/// neighbours are reused; a long reservoir memory (cap 20, the paper's) correlates frames so that
/// temporal accumulation averages little and the à-trous filter leaves blotches (24.2 dB against
/// 27.8 dB with cap 4).
struct Config {
  uint32_t candidates = 1;         ///< Light samples resampled per pixel per frame.
  uint32_t spatialNeighbours = 2;  ///< Neighbour reservoirs combined per pixel (at most 8).
  float spatialRadius = 8.0f;      ///< Pixels around the pixel the neighbours are drawn from.
  float historyCap = 4.0f;         ///< Last frame's M is capped at this many times the candidates.
  float depthTolerance = 0.1f;     ///< Relative depth difference a neighbour or history may have.
  float normalCosine = 0.9f;       ///< Least cosine between its normal and the pixel's.
};

/// A pixel's first camera-visible diffuse or glossy hit (what the integrator shades there).
struct ShadingPoint {
  glm::vec3 position{0.0f};
  glm::vec3 ng{0.0f};       ///< Geometric normal on the viewer's side.
  glm::vec3 ns{0.0f};       ///< Shading normal on the viewer's side.
  glm::vec3 wo{0.0f};       ///< Unit direction toward the viewer.
  glm::vec3 albedo{0.0f};
  float specular = 0.0f, roughness = 1.0f;
  bool specularTinted = false;   ///< MaterialDesc::specularTinted.
  float depth = 0.0f;       ///< Distance from the camera.
  InstanceId instance = kNoId;
  MaterialId material = kNoId;
  bool valid = false;       ///< False: sky, mirror, portal, or nothing hit (no reservoir).
};

/// A weighted light sample (Bitterli et al.'s reservoir after resampling).
struct Reservoir {
  LightPoint light;          ///< The sample kept.
  float weight = 0.0f;       ///< Its unbiased contribution weight W (0 = none or occluded).
  float count = 0.0f;        ///< M: candidates it stands for.
};

/// The shadow ray from `position` (geometric normal ng) to the light of `sample`.
Ray shadowRayTo(const glm::vec3& position, const glm::vec3& ng, const LightSample& sample);

/// Per-pixel reservoirs of one view, with last frame's as history.
class Resampler {
 public:
  /// A resampler with the given knobs and no history.
  explicit Resampler(const Config& config = {});
  /// Forgets the history.
  void reset();
  /// Runs the three steps for this frame. Pixel (x, y)'s hit is that of the camera ray through
  /// film position (x, y) + jitter of sample `sampleIndex` (as the renderer's first sample);
  /// `pixelSeedBase` is hash32(seed) as the renderer seeds pixels. `motions` and `previousCamera`
  /// (null: no history use) give each hit's previous position. Parallel over rows in the calling
  /// task arena.
  void run(const RenderScene& scene, const CameraRays& camera, uint32_t width, uint32_t height,
           uint32_t pixelSeedBase, uint32_t sampleIndex, const temporal::InstanceMotion& motions,
           const CameraRays* previousCamera);
  /// The final reservoir of pixel (x, y) after run() (weight 0 where there is none).
  const Reservoir& at(uint32_t x, uint32_t y) const { return final_[size_t{y} * width_ + x]; }
  /// True when pixel (x, y) has a hit the reservoir belongs to.
  bool covers(uint32_t x, uint32_t y) const { return points_[size_t{y} * width_ + x].valid; }
  /// Shadow rays traced by the last run() (candidates' visibility and every 1/Z test).
  uint64_t shadowRays() const { return shadowRays_; }

 private:
  struct Input {
    const Reservoir* reservoir;
    const ShadingPoint* point;
    bool knownVisible;   // its sample was tested visible from its point in this scene
  };
  /// Combines inputs[0] (the pixel's own) with the others into out, by 1/Z.
  void combine(const RenderScene& scene, const ShadingPoint& at, const Input* inputs, uint32_t count,
               uint32_t bits, Reservoir& out, uint64_t& rays) const;
  bool similar(const ShadingPoint& a, const ShadingPoint& b) const;

  Config config_;
  uint32_t width_ = 0, height_ = 0;
  bool haveHistory_ = false;
  std::vector<ShadingPoint> points_, previousPoints_;
  std::vector<Reservoir> initial_, temporal_, final_, previous_;
  temporal::GBuffer gbuffer_;
  uint64_t shadowRays_ = 0;
};

/// The first camera-visible hit of `ray` traced as the integrator's first vertex (`bits` are the
/// camera ray's random bits): invalid unless it is a diffuse or glossy surface seen directly.
ShadingPoint primaryShadingPoint(const RenderScene& scene, const CameraRays& camera, const Ray& ray, uint32_t bits,
                                 PixelSample* aovs = nullptr);

/// Unshadowed target of `light` at `point` (luminance of BSDF x radiance over the light's own
/// measure); 0 where the light sampler could not have picked it there. Fills `sample`.
float target(const LightSampler& lights, const ShadingPoint& point, const LightPoint& light, LightSample& sample);

}  // namespace pa::restir
