// pa::Renderer: owns the task arena, the editable scene, the committed scene and the film,
// and runs tiles of pixels in parallel. See renderer.h for the contract.
#include "renderer/scene/renderer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "renderer/core/prefetch.h"
#include "renderer/scene/denoise/denoiser.h"
#include "renderer/scene/denoise/fireflies.h"
#include "renderer/scene/film/film.h"
#include "renderer/scene/integrator/camera_rays.h"
#include "renderer/scene/integrator/integrator.h"
#include "renderer/scene/restir/restir.h"
#include "renderer/scene/sampling/sobol_sampler.h"
#include "renderer/scene/sampling/warp.h"
#include "renderer/scene/taau/taau.h"
#include "renderer/scene/temporal/gradients.h"
#include "renderer/scene/temporal/motion.h"
#include "renderer/scene/temporal/temporal.h"
#include "renderer/scene/world/render_scene.h"
#include "renderer/scene/world/scene_store.h"

namespace pa {

namespace {

constexpr uint32_t kTileSize = 16;
constexpr uint32_t kBlockSide = 4;   // camera-ray packets: 4x4 pixels (bvh.h kMaxPacketRays)
static_assert(kBlockSide * kBlockSide <= kMaxPacketRays && kTileSize % kBlockSide == 0);
constexpr uint32_t kMaxImageSide = 16384;
constexpr uint32_t kMaxSamplesPerPixel = 1u << 16;

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

int arenaConcurrency(uint32_t threads) {
  return threads == 0 ? tbb::task_arena::automatic : static_cast<int>(threads);
}

bool sameCamera(const Camera& a, const Camera& b) {
  return a.origin == b.origin && a.forward == b.forward && a.left == b.left && a.up == b.up && a.fovX == b.fovX &&
         a.fovY == b.fovY;
}

/// Settings that change the estimate (exposure and tonemap only change the display).
bool sameEstimate(const RenderSettings& a, const RenderSettings& b) {
  return a.width == b.width && a.height == b.height && a.integrator == b.integrator &&
         a.samplesPerPixel == b.samplesPerPixel && a.maxBounces == b.maxBounces &&
         a.radianceClamp == b.radianceClamp && a.rouletteStart == b.rouletteStart && a.seed == b.seed &&
         a.accumulateThroughEdits == b.accumulateThroughEdits && a.bakedLightAtPathEnd == b.bakedLightAtPathEnd &&
         a.lightingLook == b.lightingLook;
}

/// Settings whose change starts the temporal history again (the seed changes every frame).
bool sameTemporalEstimate(const RenderSettings& a, const RenderSettings& b) {
  return a.width == b.width && a.height == b.height && a.integrator == b.integrator &&
         a.samplesPerPixel == b.samplesPerPixel && a.maxBounces == b.maxBounces &&
         a.radianceClamp == b.radianceClamp && a.rouletteStart == b.rouletteStart &&
         a.bakedLightAtPathEnd == b.bakedLightAtPathEnd && a.lightingLook == b.lightingLook;
}

/// True when a camera sample's first hit is the surface a pixel's history shows: the same instance
/// and material as last frame's first hit, at a depth within 5% of the history's mean depth.
bool sameFirstHit(const PixelAccumulator& history, const PixelSample& sample, InstanceId lastInstance,
                  MaterialId lastMaterial) {
  if (history.samples == 0 || sample.instance != lastInstance || sample.material != lastMaterial) return false;
  if (history.depthCount == 0) return !std::isfinite(sample.depth);   // the sky then and now
  const double mean = history.depthSum / static_cast<double>(history.depthCount);
  return std::isfinite(sample.depth) && std::abs(sample.depth - mean) <= 0.05 * mean;
}

/// What a frame writes of the G-buffer: the ids always, the motion when something reads it
/// (the temporal stage, TAAU, FrameView::motion), the previous depth and normal for the
/// temporal stage only.
struct GBufferWrites {
  bool motion = true;
  bool previousSurface = true;
};

/// Asks the cache for the film's and the G-buffer's storage of pixels [x0, x1) x [y0, y1) of an
/// image `width` pixels wide, ahead of that block's samples (core/prefetch.h).
void prefetchBlock(const Film& film, const temporal::GBuffer& gbuffer, GBufferWrites writes, uint32_t width,
                   uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1) {
  const size_t n = x1 - x0;
  for (uint32_t y = y0; y < y1; ++y) {
    film.prefetchPixels(x0, y, x1 - x0);
    const size_t i = size_t{y} * width + x0;
    prefetchForWrite(std::span(gbuffer.instance).subspan(i, n));
    prefetchForWrite(std::span(gbuffer.material).subspan(i, n));
    if (!writes.motion) continue;
    prefetchForWrite(std::span(gbuffer.motion).subspan(i, n));
    if (!writes.previousSurface) continue;
    prefetchForWrite(std::span(gbuffer.previousDepth).subspan(i, n));
    prefetchForWrite(std::span(gbuffer.previousNormal).subspan(i, n));
  }
}

/// Luminance of what a sample's light reflects (radiance - emission: what the temporal stage
/// blends); NaN where not finite, and on camera-only overlays (the first-person weapon moves with
/// the camera, so last frame's camera ray does not find it where it was: the temporal gradients
/// leave it to the luminance test).
float litLuminance(const PixelSample& sample) {
  if (sample.overlay) return std::numeric_limits<float>::quiet_NaN();
  const float l = sampling::luminance(sample.radiance - sample.emission);
  return std::isfinite(l) ? l : std::numeric_limits<float>::quiet_NaN();
}

/// Film offset (0..1 in each axis) of a camera sample in its pixel: the frame's centre (pixel
/// centres, moved by TAAU's jitter) or the sampler's first two numbers.
glm::vec2 cameraSampleOffset(const RenderSettings& settings, glm::vec2 centre, const sampling::PixelSampler& sampler) {
  return settings.pixelCentres ? centre : glm::vec2(sampler.get4(0));
}

/// Temporal gradients (temporal/gradients.h): for each stratum, last frame's first sample of the
/// pixel its chosen pixel came from, traced again in this frame's scene with that frame's random
/// numbers (its seed hash and camera-sample centre), then the strata's gradients resolved. Runs
/// in the calling task arena; each stratum's result depends on it alone.
void retraceLastSamples(temporal::GradientEstimator& gradients, const temporal::GBuffer& gbuffer,
                        const RenderScene& scene, const CameraRays& previousCamera, const RenderSettings& settings,
                        uint32_t seedHash, glm::vec2 centre, uint32_t lastSeedHash, glm::vec2 lastCentre) {
  // Frames with a temporal stage never accumulate: their first sample is sample 0.
  const auto jitterOf = [&](uint32_t x, uint32_t y) {
    return cameraSampleOffset(settings, centre,
                              sampling::PixelSampler(sampling::hashCombine(seedHash, y * settings.width + x), 0));
  };
  gradients.plan(gbuffer, seedHash, jitterOf);
  const std::span<const temporal::GradientTarget> targets = gradients.targets();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, targets.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) {
      const temporal::GradientTarget& t = targets[k];
      if (!t.valid) continue;
      const sampling::PixelSampler sampler(sampling::hashCombine(lastSeedHash, t.y * settings.width + t.x), 0);
      const glm::vec2 jitter = cameraSampleOffset(settings, lastCentre, sampler);
      const PixelSample sample = traceSample(scene, previousCamera, settings, static_cast<float>(t.x) + jitter.x,
                                             static_cast<float>(t.y) + jitter.y, sampler, nullptr, nullptr, nullptr);
      gradients.record(k, litLuminance(sample));
    }
  });
  gradients.resolve();
}

void validateSettings(const RenderSettings& s) {
  if (s.width > kMaxImageSide || s.height > kMaxImageSide) {
    throw SceneError("render: image size " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                     " exceeds " + std::to_string(kMaxImageSide));
  }
  if (s.samplesPerPixel == 0 || s.samplesPerPixel > kMaxSamplesPerPixel) {
    throw SceneError("render: samplesPerPixel must be in [1, " + std::to_string(kMaxSamplesPerPixel) + "]");
  }
  if (!std::isfinite(s.exposure) || s.exposure < 0.0f) throw SceneError("render: exposure must be finite and >= 0");
  if (s.outputWidth > kMaxImageSide || s.outputHeight > kMaxImageSide) {
    throw SceneError("render: output size " + std::to_string(s.outputWidth) + "x" + std::to_string(s.outputHeight) +
                     " exceeds " + std::to_string(kMaxImageSide));
  }
  if (!std::isfinite(s.radianceClamp) || s.radianceClamp < 0.0f) {
    throw SceneError("render: radianceClamp must be finite and >= 0");
  }
}

}  // namespace

struct Renderer::Impl {
  explicit Impl(const RendererConfig& c) : config(c), arena(arenaConcurrency(c.threads)) {
    store.setBvhConfig(c.bvh);
    store.setLampVisibility(c.lampVisibility);
  }

  RendererConfig config;
  tbb::task_arena arena;
  SceneStore store;
  RenderScene scene;
  Film film;
  denoise::Denoiser denoiser;
  // After temporal accumulation the noise is lower: 4 à-trous passes (33 px reach) instead of 5.
  // oa_dm1 still view, 24 frames: 5 passes 32.66 dB, 4 passes 32.70 dB, 3 passes 32.77 dB; 4
  // keeps more reach for disoccluded pixels, which are filtered spatially only.
  denoise::Denoiser temporalDenoiser{denoise::Config{4}};
  temporal::InstanceMotion motions;     // where each instance was last frame
  temporal::GBuffer gbuffer;
  temporal::TemporalFilter temporal;
  temporal::GradientEstimator gradients;   // where the lighting changed since the last frame
  uint32_t lastSeedHash = 0;               // last frame's sampler seed and camera-sample centre,
  glm::vec2 lastCentre{0.5f};              // which its samples' retracing needs
  denoise::FireflyScratch fireflyScratch;   // spreadFireflies' arrays, kept between frames
  bool temporalLast = false;            // the last render ran the temporal stage
  restir::Resampler resampler;          // ReSTIR's reservoirs and their history
  bool restirLast = false;              // the last render resampled
  taau::Upscaler upscaler;              // TAAU's history at the output size
  uint32_t taauFrame = 0;               // frames resolved by TAAU in a row (picks the jitter)
  std::vector<glm::vec2> taauMotion;    // the G-buffer's motion without surfaces whose material changed
  bool sceneChanged = true;   // a commit happened since the last render
  bool worldChanged = true;   // ... that changed more than camera-only overlays
  SeenChanges seenSinceRender;   // what the commits since the last render changed that the camera sees
  bool environmentAttached = false;   // the committed scene has its sun/sky visibility map
  bool haveLast = false;
  double commitMsSinceRender = 0.0;   // commit() time to report with the next render
  Camera lastCamera;
  RenderSettings lastSettings;
  // startRender's work: the task and what it renders and returns.
  tbb::task_group inFlight;
  bool rendering = false;
  Camera startedCamera;
  RenderSettings startedSettings;
  FrameView startedView;
};

Renderer::Renderer(const RendererConfig& config) : impl_(std::make_unique<Impl>(config)) {}
Renderer::~Renderer() {
  if (!impl_->rendering) return;
  try {
    finishRender();   // its tasks read the scene and film about to be destroyed
  } catch (...) {
    // A failed render has nothing left to clean up.
  }
}

MeshId Renderer::addMesh(const MeshDesc& mesh) { return impl_->store.addMesh(mesh); }
void Renderer::updateMesh(MeshId id, const MeshDesc& mesh) { impl_->store.updateMesh(id, mesh); }
void Renderer::removeMesh(MeshId id) { impl_->store.removeMesh(id); }
void Renderer::reserveMeshLike(MeshId id, MeshId example) { impl_->store.reserveMeshLike(id, example); }
InstanceId Renderer::addInstance(const InstanceDesc& instance) { return impl_->store.addInstance(instance); }
void Renderer::setInstance(InstanceId id, const InstanceDesc& instance) { impl_->store.setInstance(id, instance); }
void Renderer::removeInstance(InstanceId id) { impl_->store.removeInstance(id); }
TextureId Renderer::addTexture(const TextureDesc& texture) { return impl_->store.addTexture(texture); }
void Renderer::updateTexture(TextureId id, const TextureDesc& texture) { impl_->store.updateTexture(id, texture); }
MaterialId Renderer::addMaterial(const MaterialDesc& material) { return impl_->store.addMaterial(material); }
void Renderer::setMaterial(MaterialId id, const MaterialDesc& material) { impl_->store.setMaterial(id, material); }
LightId Renderer::addLight(const LightDesc& light) { return impl_->store.addLight(light); }
void Renderer::setLight(LightId id, const LightDesc& light) { impl_->store.setLight(id, light); }
void Renderer::removeLight(LightId id) { impl_->store.removeLight(id); }
void Renderer::setSky(const SkyDesc& sky) { impl_->store.setSky(sky); }

void Renderer::setPortals(std::span<const PortalDesc> portals) { impl_->store.setPortals(portals); }
void Renderer::setFogVolumes(std::span<const FogVolumeDesc> volumes) { impl_->store.setFogVolumes(volumes); }

void Renderer::setStockDynamicLights(std::span<const StockDynamicLight> lights) {
  impl_->store.setStockDynamicLights(lights);
}

void Renderer::commit() {
  Impl& im = *impl_;
  if (!im.store.dirty()) return;
  const auto start = Clock::now();
  try {
    im.arena.execute([&] { im.store.commit(im.scene); });   // refilled in place: no allocation in steady state
    im.environmentAttached = false;
    im.worldChanged = im.worldChanged || !im.store.lastCommitOnlyCameraOverlays();
    im.seenSinceRender.merge(im.store.lastCommitSeenChanges());
  } catch (const SceneError&) {
    throw;   // validation failed before anything changed
  } catch (...) {
    im.scene = RenderScene{};   // a build failed half-way: render nothing rather than stale pointers
    throw;
  }
  im.sceneChanged = true;
  im.commitMsSinceRender += millisecondsSince(start);
}

void Renderer::prepareLights() {
  commit();
  attachLights();
}

void Renderer::attachLights() {
  Impl& im = *impl_;
  if (im.environmentAttached) return;
  im.arena.execute([&] {
    im.store.attachLights(im.scene);
    im.store.attachVisibilityMaps(im.scene);
  });
  im.environmentAttached = true;
}

void Renderer::startRender(const Camera& camera, const RenderSettings& settings) {
  Impl& im = *impl_;
  if (im.rendering) throw SceneError("startRender: the last startRender was not finished");
  validateSettings(settings);   // before anything runs: the caller hears of bad settings at once
  im.startedCamera = camera;
  im.startedSettings = settings;
  im.startedView = FrameView{};
  im.rendering = true;
  // Enqueued: the arena's worker threads take it while the caller goes on (spawned work would
  // wait in the caller's own task pool).
  im.arena.enqueue(im.inFlight.defer([this] {
    Impl& d = *impl_;
    commit();
    d.startedView = render(d.startedCamera, d.startedSettings);
  }));
}

FrameView Renderer::finishRender() {
  Impl& im = *impl_;
  if (!im.rendering) throw SceneError("finishRender: no render was started");
  // The caller joins the arena and works on the render's tasks until it is done.
  im.rendering = false;
  im.arena.execute([&] { im.inFlight.wait(); });
  return im.startedView;
}

bool Renderer::rendering() const { return impl_->rendering; }

void Renderer::forgetFrames() {
  Impl& im = *impl_;
  if (im.rendering) throw SceneError("forgetFrames: the last startRender was not finished");
  im.film.reset();
  im.temporal.reset();
  im.upscaler.reset();
  im.resampler.reset();
  im.gradients.reset();
  im.motions.reset();
  im.taauFrame = 0;
  im.temporalLast = false;
  im.restirLast = false;
  im.haveLast = false;
  im.sceneChanged = true;
  im.worldChanged = true;
}

FrameView Renderer::render(const Camera& camera, const RenderSettings& settings) {
  Impl& im = *impl_;
  validateSettings(settings);
  if (settings.width == 0 || settings.height == 0) return FrameView{};
  CameraRays rays(camera, settings.width, settings.height);
  if (settings.taau && settings.outputHeight > settings.height) rays.setFootprintHeight(settings.outputHeight);
  RenderTimings timings;
  timings.commitMs = std::exchange(im.commitMsSinceRender, 0.0);
  auto phaseStart = Clock::now();
  const auto endPhase = [&phaseStart](double& ms) {
    ms = millisecondsSince(phaseStart);
    phaseStart = Clock::now();
  };

  if (settings.integrator != Integrator::Lightmap) attachLights();   // Lightmap never samples lights
  double attachMs = 0.0;
  endPhase(attachMs);
  timings.commitMs += attachMs;
  im.film.resize(settings.width, settings.height);
  // Motion: last frame's camera, in this frame's pixels (also across a change of size, which
  // TAAU reprojects through; the temporal stage and ReSTIR start again then), and where each
  // instance was.
  std::optional<CameraRays> previousRays;
  if (im.haveLast) {
    previousRays.emplace(im.lastCamera, settings.width, settings.height);
    // The texture footprints of this frame's rays (temporal gradients retrace last frame's).
    if (settings.taau && settings.outputHeight > settings.height) previousRays->setFootprintHeight(settings.outputHeight);
  }
  im.motions.beginFrame(im.scene.world, im.scene.overlay);
  im.gbuffer.resize(settings.width, settings.height);
  const bool temporalOn = settings.temporal && !settings.accumulate && settings.integrator != Integrator::Lightmap;
  const bool temporalReset = !temporalOn || !im.temporalLast || !sameTemporalEstimate(settings, im.lastSettings);
  if (temporalReset) im.temporal.reset();
  im.temporalLast = temporalOn;
  // The motion only where something reads it; the previous depth and normal for the temporal stage.
  const GBufferWrites gbufferWrites{temporalOn || settings.taau || settings.motionVectors, temporalOn};
  const bool restirOn = settings.restir && settings.integrator != Integrator::Lightmap;
  if (!restirOn || !im.restirLast) im.resampler.reset();
  // Temporal gradients retrace last frame's first samples: the same estimate, without ReSTIR
  // (whose first samples depend on the reservoirs), from a frame that recorded them.
  const bool gradientsOn = temporalOn && settings.temporalGradients && !restirOn;
  if (!gradientsOn || temporalReset || im.restirLast) im.gradients.reset();
  if (gradientsOn) {
    temporal::GradientConfig gradientConfig = im.gradients.config();
    gradientConfig.stratum = settings.gradientStratum;
    im.gradients.configure(gradientConfig);
    im.gradients.beginFrame(settings.width, settings.height);
  }
  im.restirLast = restirOn;
  // accumulateThroughEdits: a still view keeps its accumulation through world edits; a pixel that
  // shows an edited instance, material or sky (this frame or the last) starts again when its first
  // hit is now another surface; lighting edits are averaged over time as in a long exposure
  // (seen_changes.h).
  const bool unchangedOrSeenOnly =
      !im.worldChanged || (settings.accumulateThroughEdits && !im.seenSinceRender.everything);
  const bool keep = settings.accumulate && im.haveLast && unchangedOrSeenOnly && sameCamera(camera, im.lastCamera) &&
                    sameEstimate(settings, im.lastSettings) && im.film.canResume();
  // A frame of one sample per pixel that is not accumulated (the game's lightmap, direct and path
  // frames): each sample is its pixel's resolved value, written without the accumulators; the
  // temporal stage and the denoiser then work on those values in place.
  const bool singleSample = !settings.accumulate && settings.samplesPerPixel == 1;
  const bool filtered = settings.denoise || temporalOn;
  // Such a frame's emission, albedo and normal planes are read by the temporal stage, the
  // denoiser and the lighting look, and by the caller through FrameView when it asks for them.
  const bool filmAovs =
      !singleSample || filtered || settings.surfaceAovs || settings.lightingLook != LightingLook::Physical;
  if (singleSample) im.film.beginSingleSampleFrame(filmAovs, filtered);
  else if (!keep) im.film.reset();
  else im.film.resumeAccumulation();
  // Camera-only overlays changed (the first-person weapon moved): the pixels they covered last
  // frame or cover now start again.
  const bool restartOverlayPixels = keep && im.sceneChanged;
  const bool restartSeenPixels = keep && im.worldChanged && !im.seenSinceRender.empty();
  const bool scenePortals = !im.scene.portals.empty();
  im.haveLast = true;
  im.sceneChanged = false;
  im.worldChanged = false;
  im.lastCamera = camera;
  im.lastSettings = settings;

  // TAAU: one-sample pixel-centre frames move their samples by a sub-pixel jitter each frame.
  if (!settings.taau) im.upscaler.reset();
  const uint32_t taauFrame = settings.taau ? im.taauFrame++ : (im.taauFrame = 0);
  const glm::vec2 centre = glm::vec2(0.5f) + (settings.taau && settings.pixelCentres ? taau::jitter(taauFrame) : glm::vec2(0.0f));
  const uint32_t tilesX = (settings.width + kTileSize - 1) / kTileSize;
  const uint32_t tilesY = (settings.height + kTileSize - 1) / kTileSize;
  const uint32_t firstSample = im.film.frames() * settings.samplesPerPixel;
  const uint32_t seedHash = sampling::hash32(settings.seed);
  const RenderScene& scene = im.scene;
  Film& film = im.film;
  temporal::GBuffer& gbuffer = im.gbuffer;
  const temporal::InstanceMotion& motions = im.motions;
  const SeenChanges& seen = im.seenSinceRender;
  const CameraRays* previousCamera = previousRays ? &*previousRays : nullptr;

  const restir::Resampler& resampler = im.resampler;
  const std::span<float> gradientLuminance = gradientsOn ? im.gradients.sampleLuminance() : std::span<float>();
  std::span<const float> historyDrop;   // the gradients' answer, when they ran (FrameView::historyDrop)
  im.arena.execute([&] {
    if (restirOn) {
      im.resampler.run(scene, rays, settings.width, settings.height, seedHash, firstSample, motions, previousCamera);
      endPhase(timings.resampleMs);
    }
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, tilesX * tilesY, 1), [&](const tbb::blocked_range<uint32_t>& r) {
      TriangleMemo memo;   // neighbouring samples mostly end on a few triangles
      for (uint32_t tile = r.begin(); tile != r.end(); ++tile) {
        const uint32_t x0 = (tile % tilesX) * kTileSize;
        const uint32_t y0 = (tile / tilesX) * kTileSize;
        const uint32_t x1 = std::min(x0 + kTileSize, settings.width);
        const uint32_t y1 = std::min(y0 + kTileSize, settings.height);
        // Blocks of 4x4 pixels: each sample's camera rays of a block are traced as one packet.
        prefetchBlock(film, gbuffer, gbufferWrites, settings.width, x0, y0, std::min(x0 + kBlockSide, x1),
                      std::min(y0 + kBlockSide, y1));
        for (uint32_t by = y0; by < y1; by += kBlockSide) {
          for (uint32_t bx = x0; bx < x1; bx += kBlockSide) {
            {   // the next block's storage, while this one is traced
              const bool rowEnds = bx + kBlockSide >= x1;
              const uint32_t nx = rowEnds ? x0 : bx + kBlockSide, ny = rowEnds ? by + kBlockSide : by;
              if (ny < y1)
                prefetchBlock(film, gbuffer, gbufferWrites, settings.width, nx, ny, std::min(nx + kBlockSide, x1),
                              std::min(ny + kBlockSide, y1));
            }
            struct PixelState {
              uint32_t x, y, seed;
              bool overlaySeen = false, coveredBefore = false, restarted = false;
              InstanceId lastInstance = kNoId;   // last frame's first hit (accumulateThroughEdits)
              MaterialId lastMaterial = kNoId;
            };
            std::array<PixelState, kBlockSide * kBlockSide> pixels;
            uint32_t count = 0;
            for (uint32_t y = by; y < std::min(by + kBlockSide, y1); ++y)
              for (uint32_t x = bx; x < std::min(bx + kBlockSide, x1); ++x) {
                PixelState& p = pixels[count++];
                p = {x, y, sampling::hashCombine(seedHash, y * settings.width + x)};
                if (!restartOverlayPixels && !restartSeenPixels) continue;   // no pixel restarts
                // Last frame's first hit (the G-buffer is written by this frame's first sample below).
                const size_t i = size_t{y} * settings.width + x;
                const bool showedEdit =
                    restartSeenPixels && seen.seenAt(gbuffer.instance[i], gbuffer.material[i], scenePortals);
                p.coveredBefore = (restartOverlayPixels && film.overlayAt(x, y)) || showedEdit;
                p.lastInstance = gbuffer.instance[i];
                p.lastMaterial = gbuffer.material[i];
              }
            std::array<TracedCameraRay, kBlockSide * kBlockSide> traced;
            // The Lightmap look composes see-through layers in display values (DisplayComposite).
            for (TracedCameraRay& r : traced) r.additive.displayValues = settings.integrator == Integrator::Lightmap;
            std::array<glm::vec2, kBlockSide * kBlockSide> jitters;   // this sample's, per pixel
            for (uint32_t s = 0; s < settings.samplesPerPixel; ++s) {
              for (uint32_t i = 0; i < count; ++i)
                jitters[i] = cameraSampleOffset(settings, centre, sampling::PixelSampler(pixels[i].seed, firstSample + s));
              if (settings.cameraPackets) {
                for (uint32_t i = 0; i < count; ++i) {
                  rays.generate(static_cast<float>(pixels[i].x) + jitters[i].x,
                                static_cast<float>(pixels[i].y) + jitters[i].y, traced[i].ray);
                  traced[i].randomBits = cameraRayBits(sampling::PixelSampler(pixels[i].seed, firstSample + s));
                }
                scene.intersectCameraPacket(std::span(traced.data(), count));
                // The Lightmap look fogs only surfaces inside a fog volume: most packets end outside all.
                if (settings.integrator == Integrator::Lightmap) scene.markFogFreeEnds(std::span(traced.data(), count));
              }
              for (uint32_t i = 0; i < count; ++i) {
                PixelState& p = pixels[i];
                const sampling::PixelSampler sampler(p.seed, firstSample + s);
                const glm::vec2 jitter = jitters[i];
                ResampledLight resampled;
                const bool useResampled = restirOn && s == 0 && resampler.covers(p.x, p.y);
                if (useResampled) resampled = {resampler.at(p.x, p.y).light, resampler.at(p.x, p.y).weight};
                const PixelSample sample =
                    traceSample(scene, rays, settings, static_cast<float>(p.x) + jitter.x,
                                static_cast<float>(p.y) + jitter.y, sampler, settings.cameraPackets ? &traced[i] : nullptr,
                                useResampled ? &resampled : nullptr, &memo);
                if (s == 0 && gradientsOn) {
                  gradientLuminance[size_t{p.y} * settings.width + p.x] = litLuminance(sample);
                }
                if (s == 0 && !gbufferWrites.motion) {
                  gbuffer.writeIds(size_t{p.y} * settings.width + p.x, sample);
                } else if (s == 0) {
                  gbuffer.write(size_t{p.y} * settings.width + p.x, sample, static_cast<float>(p.x) + jitter.x,
                                static_cast<float>(p.y) + jitter.y, motions, previousCamera,
                                gbufferWrites.previousSurface);
                }
                p.overlaySeen = p.overlaySeen || sample.overlay;
                if (singleSample) {
                  film.writeSample(p.x, p.y, sample);
                  continue;
                }
                PixelAccumulator& acc = film.pixel(p.x, p.y);
                const bool showsEdit =
                    sample.overlay || (restartSeenPixels && seen.seenAt(sample.instance, sample.material, scenePortals));
                // Through edits, a pixel that shows one starts again only when its first hit is
                // another surface now; the same surface moved a little (the view weapon's idle
                // drift, an animated texture) keeps accumulating, as a long exposure would.
                if ((restartOverlayPixels || restartSeenPixels) && !p.restarted && (p.coveredBefore || showsEdit) &&
                    !(settings.accumulateThroughEdits && sameFirstHit(acc, sample, p.lastInstance, p.lastMaterial))) {
                  acc = PixelAccumulator{};   // the old picture of what changed, or what it now shows, goes
                  p.restarted = true;
                }
                acc.add(sample);
              }
            }
            for (uint32_t i = 0; i < count; ++i) film.setOverlayAt(pixels[i].x, pixels[i].y, pixels[i].overlaySeen);
          }
        }
      }
    });
    film.finishFrame();
    endPhase(timings.traceMs);
    const auto forRows = [&](auto&& body) {
      tbb::parallel_for(tbb::blocked_range<uint32_t>(0, settings.height, 8),
                        [&](const tbb::blocked_range<uint32_t>& r) { body(r.begin(), r.end()); });
    };
    if (!filtered) {   // a single-sample frame's resolved buffers hold its samples already
      if (singleSample)
        forRows([&](uint32_t y0, uint32_t y1) { film.encodeRows(y0, y1, settings.exposure, settings.tonemap, settings.lightingLook); });
      else
        forRows([&](uint32_t y0, uint32_t y1) { film.resolveRows(y0, y1, settings.exposure, settings.tonemap, settings.lightingLook); });
      endPhase(timings.resolveMs);
      return;
    }
    if (!singleSample) forRows([&](uint32_t y0, uint32_t y1) { film.resolveMeanRows(y0, y1); });
    double meanMs = 0.0;
    endPhase(meanMs);
    if (gradientsOn && im.gradients.havePrevious() && previousCamera != nullptr) {
      retraceLastSamples(im.gradients, gbuffer, scene, *previousCamera, settings, seedHash, centre, im.lastSeedHash,
                         im.lastCentre);
    }
    if (temporalOn) {
      const temporal::FrameInputs inputs{film.width(),  film.height(), film.emission(), film.albedo(),
                                         film.normal(), film.depth(),  &gbuffer,
                                         gradientsOn ? im.gradients.historyDrop() : std::span<const float>()};
      im.temporal.accumulate(inputs, film.resolvedRadiance());
      endPhase(timings.temporalMs);
    }
    if (settings.spreadFireflies) {   // after the history's robust blend, before the denoiser
      const denoise::FireflyInputs fireflies{film.width(), film.height(), film.emission(), film.normal(), film.depth()};
      denoise::spreadFireflies(fireflies, film.resolvedRadiance(), im.fireflyScratch);
    }
    if (settings.denoise) {
      denoise::Guides guides{film.width(), film.height(), film.albedo(), film.normal(), film.depth(),
                             film.variance(), uint64_t{film.frames()} * settings.samplesPerPixel,
                             film.emission(), {}};
      if (temporalOn) {
        guides.variance = im.temporal.variance();
        guides.historyLength = im.temporal.historyLength();
        im.temporalDenoiser.apply(guides, film.resolvedRadiance(), im.temporal.feedback());
      } else {
        im.denoiser.apply(guides, film.resolvedRadiance());
      }
      endPhase(timings.denoiseMs);
    }
    if (temporalOn) im.temporal.endFrame();
    if (gradientsOn) {
      historyDrop = im.gradients.historyDrop();
      im.gradients.endFrame();
      im.lastSeedHash = seedHash;
      im.lastCentre = centre;
    }
    forRows([&](uint32_t y0, uint32_t y1) { film.encodeRows(y0, y1, settings.exposure, settings.tonemap, settings.lightingLook); });
    endPhase(timings.resolveMs);
    timings.resolveMs += meanMs;
  });
  // TAAU: a surface whose material changed since the last frame (a scrolled or animated texture)
  // moved where the geometry did not: no history there.
  std::span<const glm::vec2> taauMotion = gbuffer.motion;
  if (settings.taau && im.seenSinceRender.anyObject) {
    im.taauMotion.assign(gbuffer.motion.begin(), gbuffer.motion.end());   // memory kept between frames
    for (size_t i = 0; i < im.taauMotion.size(); ++i)
      if (im.seenSinceRender.materialEdited(gbuffer.material[i])) im.taauMotion[i] = glm::vec2(temporal::GBuffer::kNoMotion);
    taauMotion = im.taauMotion;
  }
  im.seenSinceRender.clear();

  FrameView view;
  view.outputWidth = film.width();
  view.outputHeight = film.height();
  view.output = film.rgba8();
  if (settings.taau) {
    const uint32_t outWidth = settings.outputWidth != 0 ? settings.outputWidth : settings.width;
    const uint32_t outHeight = settings.outputHeight != 0 ? settings.outputHeight : settings.height;
    const taau::Frame frame{film.width(), film.height(), film.rgba8(), taauMotion, film.depth(), gbuffer.instance,
                            centre - glm::vec2(0.5f), &camera};
    std::span<const uint8_t> upscaled;
    im.arena.execute([&] { upscaled = im.upscaler.resolve(frame, outWidth, outHeight); });
    if (!upscaled.empty()) {
      view.outputWidth = outWidth;
      view.outputHeight = outHeight;
      view.output = upscaled;
    }
    endPhase(timings.taauMs);
  }
  view.width = film.width();
  view.height = film.height();
  view.accumulatedFrames = film.frames();
  view.radiance = film.radiance();
  if (filmAovs) {
    view.albedo = film.albedo();
    view.normal = film.normal();
  }
  view.depth = film.depth();
  view.variance = film.variance();
  view.rgba8 = film.rgba8();
  if (gbufferWrites.motion) view.motion = gbuffer.motion;
  view.instance = gbuffer.instance;
  view.material = gbuffer.material;
  if (temporalOn) view.historyLength = im.temporal.historyLength();
  if (gradientsOn) view.historyDrop = historyDrop;
  view.timings = timings;
  return view;
}

}  // namespace pa
