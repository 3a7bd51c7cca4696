#pragma once
// pa::Renderer: the flat scene API (in the spirit of Lighthouse 2's RenderCore).
// Set meshes, instances, textures, materials, lights, sky; commit(); render().
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "renderer/bvh/bvh.h"
#include "renderer/scene/scene_types.h"

namespace pa {

/// Renderer-wide configuration fixed at construction.
struct RendererConfig {
  uint32_t threads = 0;   ///< Worker threads for builds and rendering; 0 = all cores.
  /// How meshes' BVHs are built and which kernels trace them: allowAvx512 false keeps the AVX2
  /// kernels and 8-wide layout that CPUs without AVX-512 run, to measure them on one that has it.
  BvhBuildConfig bvh{};
  /// Lamps that no shadow ray from a region's surfaces reached are chosen less often there
  /// (lights/lamp_visibility.h: traced once per scene, unbiased); false weighs every lamp by its
  /// unshadowed contribution alone.
  bool lampVisibility = true;
};

/// Where one render() call's time went (milliseconds, wall clock on the calling thread).
struct RenderTimings {
  double commitMs = 0.0;    ///< commit() calls since the previous render: BLAS builds/refits, TLAS, light tables.
  double resampleMs = 0.0;  ///< Reservoir resampling of direct light before tracing (0 when off).
  double traceMs = 0.0;     ///< Camera, bounce and shadow rays with their shading (one pass per pixel).
  double temporalMs = 0.0;  ///< Temporal accumulation with its gradients' retraced samples (0 when off).
  double denoiseMs = 0.0;   ///< The denoiser (0 when off).
  double resolveMs = 0.0;   ///< Film resolve: means, AOVs, exposure, tonemap, sRGB encode.
  double taauMs = 0.0;      ///< Temporal anti-aliasing and upscaling (0 when off).
};

/// Output of render(): linear HDR radiance (running mean) plus AOVs for denoising, and the
/// tonemapped sRGB RGBA8 image. All arrays are width*height, row-major from the top row.
struct FrameView {
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t accumulatedFrames = 0;        ///< How many render() calls the mean covers.
  std::span<const glm::vec3> radiance;   ///< Mean linear radiance.
  std::span<const glm::vec3> albedo;     ///< First-hit albedo (mean).
  std::span<const glm::vec3> normal;     ///< First-hit shading normal, world space (mean).
  std::span<const float> depth;          ///< First-hit distance along the ray (inf = sky).
  std::span<const float> variance;       ///< Per-pixel variance of the mean's luminance estimate.
  std::span<const uint8_t> rgba8;        ///< Exposure + tonemap + sRGB, alpha 255.
  /// The picture to show, outputWidth x outputHeight RGBA8: TAAU's (RenderSettings::taau), else rgba8.
  uint32_t outputWidth = 0;
  uint32_t outputHeight = 0;   ///< See outputWidth.
  std::span<const uint8_t> output;   ///< See outputWidth.
  /// G-buffer of the first camera sample of each pixel: previous film position minus this one in
  /// pixels (NaN where there is none: sky, seen through a portal, an instance new this frame, or
  /// the first frame), the instance and material index hit (kNoId = none / default material).
  std::span<const glm::vec2> motion;
  std::span<const InstanceId> instance;
  std::span<const MaterialId> material;
  /// Frames in each pixel's temporal history (RenderSettings::temporal; empty when off).
  std::span<const float> historyLength;
  /// Per pixel, the share (0..1) of its history the temporal gradients dropped because the
  /// lighting there changed (RenderSettings::temporalGradients; empty when they did not run).
  std::span<const float> historyDrop;
  RenderTimings timings;                 ///< What this call (and the commits before it) cost.
};

/// The path tracer and its scene. Not thread-safe: call from one thread.
/// Every setter validates its input and throws SceneError with a clear message.
class Renderer {
 public:
  explicit Renderer(const RendererConfig& config = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Adds a mesh (arrays are copied).
  MeshId addMesh(const MeshDesc& mesh);
  /// Replaces a mesh's data. Same vertex and index counts on a dynamic mesh -> refit.
  void updateMesh(MeshId id, const MeshDesc& mesh);
  /// Removes a mesh; instances that still use it are an error at commit().
  void removeMesh(MeshId id);
  /// Gives mesh id at least the memory mesh example holds (arrays, pending copy, BVH), so that
  /// its updates up to example's size and shape allocate nothing (dynamic meshes in play).
  void reserveMeshLike(MeshId id, MeshId example);

  /// Adds an instance of a mesh.
  InstanceId addInstance(const InstanceDesc& instance);
  /// Replaces an instance's description.
  void setInstance(InstanceId id, const InstanceDesc& instance);
  /// Removes one instance.
  void removeInstance(InstanceId id);

  /// Adds a texture (pixels copied, mipmaps built).
  TextureId addTexture(const TextureDesc& texture);
  /// Replaces a texture's pixels (e.g. cinematics).
  void updateTexture(TextureId id, const TextureDesc& texture);

  /// Adds a material.
  MaterialId addMaterial(const MaterialDesc& material);
  /// Replaces a material (e.g. per-frame uv animation).
  void setMaterial(MaterialId id, const MaterialDesc& material);

  /// Adds an analytic light.
  LightId addLight(const LightDesc& light);
  /// Replaces a light.
  void setLight(LightId id, const LightDesc& light);
  /// Removes a light.
  void removeLight(LightId id);

  /// Sets the environment.
  void setSky(const SkyDesc& sky);
  /// Replaces every portal (mirror-material windows to elsewhere; see scene_types.h).
  void setPortals(std::span<const PortalDesc> portals);
  /// Replaces every fog volume (planes copied; see scene_types.h for what fog does to rays).
  void setFogVolumes(std::span<const FogVolumeDesc> volumes);
  /// Replaces the stock dynamic lights (the Lightmap look's dynamic-light pass; scene_types.h).
  void setStockDynamicLights(std::span<const StockDynamicLight> lights);

  /// Makes all changes since the last commit visible to render(): builds changed BLASes,
  /// rebuilds the TLAS and the light sampling tables; resets accumulation if anything changed.
  void commit();
  /// commit(), then gathers what the traced integrators need of the committed scene before their
  /// first render: the light sampling tables and the sun/sky visibility map (cached per map; a
  /// few hundred milliseconds on a map with open sky). For a loading screen; render() does it
  /// itself when it has not been done.
  void prepareLights();

  /// Renders one frame of settings.samplesPerPixel samples per pixel and returns the film.
  /// Accumulation continues while camera, settings and scene are unchanged since the last call.
  /// The returned views stay valid until the next render() call; width or height 0 renders
  /// nothing and returns an empty view. Sees the scene as of the last commit().
  FrameView render(const Camera& camera, const RenderSettings& settings);

  /// commit() and render(camera, settings) on the renderer's threads: returns at once, so that
  /// the caller can do other work meanwhile. Until finishRender() returns, call no other method
  /// and read no view of an earlier render.
  void startRender(const Camera& camera, const RenderSettings& settings);
  /// Waits for the render startRender() began (the calling thread helps with its work) and
  /// returns its frame, as render() would have; rethrows what commit() or render() threw.
  FrameView finishRender();
  /// A render started by startRender() has not been finished.
  bool rendering() const;

  /// Forgets every frame rendered so far (accumulation, temporal and TAAU history and jitter,
  /// reservoirs, gradients, instance motion, the last camera): the next render is the one a new
  /// Renderer over this scene makes. The frame buffers keep their memory.
  void forgetFrames();

 private:
  /// The committed scene's light sampling tables and sun/sky visibility map, once per commit.
  void attachLights();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pa
