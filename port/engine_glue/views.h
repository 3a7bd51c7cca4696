#pragma once
// Turns a refdef_t plus the scene's entities, polygons and lights into a traced picture
// (through pa::Renderer and the world bridged from q3::WorldScene).
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "port/engine_glue/ioq3_abi.h"
#include "port/engine_glue/settings.h"

namespace glue {

class Engine;
class World;
class ShaderScripts;
class ImageCache;
class ShaderRegistry;
class ModelRegistry;
class SceneFrame;

/// A view's eye and axes in world space (refdef_t's vieworg and viewaxis rows).
struct ViewAxes {
  glm::vec3 origin, forward, left, up;
};

/// The eye and axes of `view`.
inline ViewAxes viewAxesOf(const q3abi::refdef_t& view) {
  const auto row = [&](int a) { return glm::vec3(view.viewaxis[a][0], view.viewaxis[a][1], view.viewaxis[a][2]); };
  return {glm::vec3(view.vieworg[0], view.vieworg[1], view.vieworg[2]), row(0), row(1), row(2)};
}

/// Where a traced view's time went, in milliseconds.
struct ViewTimings {
  double sceneMs = 0.0;     ///< Entities, effects, lights, sky and materials into the renderer's scene.
  double commitMs = 0.0;    ///< The renderer's commit: BLAS builds and refits, TLAS, light tables.
  double traceMs = 0.0;     ///< Rays and shading.
  double temporalMs = 0.0;  ///< Temporal accumulation.
  double denoiseMs = 0.0;   ///< Denoiser.
  double resolveMs = 0.0;   ///< Film resolve and display encode.
  double animationMs = 0.0;       ///< Part of sceneMs: world materials moved to the shader time.
  double animationUpdates = 0.0;  ///< Materials replaced for shader animation (world and entities).
  double resampleMs = 0.0;  ///< Reservoir resampling of direct light (ReSTIR), before tracing.
  double taauMs = 0.0;      ///< Temporal anti-aliasing and upscaling to the window's size.
};

/// A traced view: RGBA8 (width x height, the view's size with TAAU, else the traced size), top
/// row first; alpha 0 where nothing was hit (HUD model views).
struct TracedPicture {
  int width = 0;
  int height = 0;
  const uint8_t* rgba = nullptr;
  ViewTimings timings;
  uint32_t accumulatedFrames = 1;   ///< Frames averaged in this picture (the reference preset's history).
  int filmWidth = 0;    ///< Size of the film arrays below (the traced size).
  int filmHeight = 0;   ///< See filmWidth.
  /// The film behind the picture, filmWidth x filmHeight, valid until this ViewRenderer renders again:
  /// linear radiance (after denoising and temporal accumulation when those are on) and the
  /// variance of each pixel's mean luminance over this frame's samples (empty when unknown).
  std::span<const glm::vec3> radiance;
  std::span<const float> variance;
  /// First-hit distance along each pixel's camera ray (+inf = sky; empty when unknown).
  std::span<const float> depth;
};

/// Owns the path tracer and what it knows of the world.
class ViewRenderer {
 public:
  /// `threads` = r_pt_threads (0: all cores); `avx2Kernels` = r_pt_isa avx2 (RendererConfig::bvh);
  /// `lampVisibility` = r_pt_lamp_vis (RendererConfig::lampVisibility).
  ViewRenderer(const Engine& engine, int threads, bool avx2Kernels, bool lampVisibility);
  ~ViewRenderer();
  ViewRenderer(const ViewRenderer&) = delete;
  ViewRenderer& operator=(const ViewRenderer&) = delete;

  /// The stock picture cvars for what is loaded next (r_picmip and r_intensity on world and model
  /// textures, r_mapOverBrightBits on baked light).
  void setPicture(const PictureSettings& picture);
  /// Builds the world's meshes, materials and lights from the parsed map.
  void loadWorld(const World& world, const ShaderScripts& scripts, ImageCache& images);
  /// Drops the world (map change).
  void clearWorld();
  /// RemapShader happened: materials must be re-resolved.
  void shadersChanged();
  /// Does what the first view would do once for the whole map (EndRegistration: during loading,
  /// as the stock renderer loads its images, not in the first frame of play): makes the materials
  /// and textures of every shader registered so far and, for the world's views (`withWorld`), shows
  /// the world as the preset looks at it (sky, glowing surfaces) and commits it (the traced
  /// presets' light structures). Without `withWorld`: for model views (no 2D pictures).
  void prepareForPlay(ShaderRegistry& shaders, const TracerSettings& settings, bool withWorld);
  /// After prepareForPlay(world): traces a throw-away world view of width x height (the
  /// window) from the map's first spawn point and forgets it, so that the first frame of play
  /// finds the frame buffers of every stage made and touched (about a hundred milliseconds it
  /// would otherwise stall for). Returns the picture's size, as render() would give it (0 x 0
  /// when nothing was traced).
  std::pair<int, int> warmUp(const TracerSettings& settings, int width, int height);
  /// Traces one view; nullopt when nothing can be drawn (no tracer available).
  /// `world` is null for RDF_NOWORLDMODEL views.
  std::optional<TracedPicture> render(const q3abi::refdef_t& view, const SceneFrame& scene,
                                      const TracerSettings& settings, ShaderRegistry& shaders,
                                      const ModelRegistry& models, const World* world);
  /// What render() does, with the tracing left running on the renderer's threads: the scene is
  /// set up here, and finish() waits for the picture. Any other call first waits for it and
  /// drops it.
  void start(const q3abi::refdef_t& view, const SceneFrame& scene, const TracerSettings& settings,
             ShaderRegistry& shaders, const ModelRegistry& models, const World* world);
  /// A view start() began is being traced or waits for finish().
  bool started() const;
  /// The picture of the view start() began (waiting for it); nullopt when none was started
  /// or when this build has no tracer. Throws what tracing threw.
  std::optional<TracedPicture> finish();
  /// True when this build traces views (pa::Renderer linked in).
  static bool available();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace glue
