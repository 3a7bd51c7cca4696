// A frame: BeginFrame, 3D views (ClearScene, adds, RenderScene), 2D (SetColor,
// DrawStretchPic, DrawStretchRaw), EndFrame. Everything is drawn in call order.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "port/engine_glue/allocation_counter.h"
#include "port/engine_glue/module.h"
#include "port/engine_glue/views.h"

namespace glue {
namespace {

bool finiteRect(float x, float y, float w, float h) {
  return std::isfinite(x) && std::isfinite(y) && std::isfinite(w) && std::isfinite(h);
}

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// Adds the milliseconds a scope takes to `total`.
class ScopeTimer {
 public:
  explicit ScopeTimer(double& total) : total_(total), start_(Clock::now()) {}
  ~ScopeTimer() { total_ += millisecondsSince(start_); }
  ScopeTimer(const ScopeTimer&) = delete;
  ScopeTimer& operator=(const ScopeTimer&) = delete;

 private:
  double& total_;
  Clock::time_point start_;
};

/// Adds `scale` x each of t's timings to sum's (scale -1: subtracts them).
void addTimings(ViewTimings& sum, const ViewTimings& t, double scale = 1.0) {
  sum.sceneMs += scale * t.sceneMs;
  sum.commitMs += scale * t.commitMs;
  sum.traceMs += scale * t.traceMs;
  sum.temporalMs += scale * t.temporalMs;
  sum.denoiseMs += scale * t.denoiseMs;
  sum.resolveMs += scale * t.resolveMs;
  sum.animationMs += scale * t.animationMs;
  sum.animationUpdates += scale * t.animationUpdates;
  sum.resampleMs += scale * t.resampleMs;
  sum.taauMs += scale * t.taauMs;
}

/// The phases of `b` less those of `a` (the ms sums and the views; not the period's bookkeeping).
FrameStats phasesSince(const FrameStats& a, const FrameStats& b) {
  FrameStats d;
  d.views = b.views - a.views;
  d.modelViews = b.modelViews - a.modelViews;
  d.world = b.world;
  addTimings(d.world, a.world, -1.0);
  d.uploadMs = b.uploadMs - a.uploadMs;
  d.modelViewMs = b.modelViewMs - a.modelViewMs;
  d.overlay2dMs = b.overlay2dMs - a.overlay2dMs;
  d.presentMs = b.presentMs - a.presentMs;
  d.offThreadMs = b.offThreadMs - a.offThreadMs;
  d.waitMs = b.waitMs - a.waitMs;
  return d;
}

/// What of a frame (or a period's frames) ran on the game's thread in our phases: a pipelined
/// view's tracing ran beside it, waited for in waitMs.
double accountedMs(const FrameStats& s) {
  return s.world.sceneMs + s.world.commitMs + s.world.resampleMs + s.world.traceMs + s.world.temporalMs +
         s.world.denoiseMs + s.world.resolveMs + s.world.taauMs + s.uploadMs + s.modelViewMs + s.overlay2dMs +
         s.presentMs - s.offThreadMs + s.waitMs;
}

/// Frames that drew a view, at least this long and at least kSlowFrameFactor times the last
/// period's mean frame with a world view, are described one by one with r_pt_stats (a hitch a
/// player sees).
constexpr double kSlowFrameMs = 50.0;
constexpr double kSlowFrameFactor = 2.0;
/// At most this many of them a stats period (2 s).
constexpr int kSlowFramesPerPeriod = 8;

}  // namespace

void Module::beginFrame(int /*stereoFrame*/) {
  if (!window_.isOpen()) return;
  frameStartMs_ = engine_.milliseconds();
  const Clock::time_point now = Clock::now();
  const TracerSettings tracer = settings_.tracer(engine_);
  if (frameBegan_ != Clock::time_point{}) {
    const double lastFrameMs = std::chrono::duration<double, std::milli>(now - frameBegan_).count();
    stats_.frameMs += lastFrameMs;
    stats_.maxFrameMs = std::max(stats_.maxFrameMs, lastFrameMs);
    if (lastFrame_.views > 0) {
      stats_.viewFramesMs += lastFrameMs;
      stats_.viewFrames += 1;
    }
    // Frames that drew no view (loading screens, menus) are the engine's: not described.
    const bool drewView = lastFrame_.views > 0 || lastFrame_.modelViews > 0;
    if (tracer.printStats && drewView && lastFrameMs >= std::max(kSlowFrameMs, kSlowFrameFactor * lastPeriodFrameMs_))
      printSlowFrame(lastFrameMs);
    resolution_.update(lastFrameMs, tracer.targetFps, tracer.minScale);   // r_pt_fps 0: forgets
  }
  frameBegan_ = now;
  frameStart_ = stats_;
  lastFrame_ = FrameStats{};   // a frame that never ends (no window) describes nothing
  modelViewsThisFrame_ = 0;
  if (settings_.gammaChanged()) updateDisplayRamp();
  overlay_.beginFrame(window_.width(), window_.height(), window_.pictureFillsSurface());
  frameOpen_ = true;
  filmCapture_.clear();
}

void Module::endFrame(int* frontEndMsec, int* backEndMsec) {
  if (frontEndMsec != nullptr) *frontEndMsec = 0;
  if (backEndMsec != nullptr) *backEndMsec = 0;
  if (!window_.isOpen() || !frameOpen_) return;
  {
    const ScopeTimer present(stats_.presentMs);
    overlay_.finishDrawing();
    // r_gamma: the frame through the display's ramp (stock screenshots carry the ramp too).
    if (!rampIsIdentity_) overlay_.applyRamp(displayRamp_);
    // Screenshot commands ran during the frame: capture what was drawn before it is shown.
    std::vector<ScreenshotRequest> shots;
    shots.swap(pendingShots_);
    for (const ScreenshotRequest& request : shots) takeScreenshot(request);
    if (pendingVideo_) {
      const VideoFrameRequest video = *pendingVideo_;
      pendingVideo_.reset();
      captureVideoFrame(video);
    }
    window_.swap();
  }
  frameOpen_ = false;
  const int now = engine_.milliseconds();
  if (frontEndMsec != nullptr) *frontEndMsec = traceMsThisFrame_;
  if (backEndMsec != nullptr) *backEndMsec = now - frameStartMs_ - traceMsThisFrame_;
  stats_.frames += 1;
  framesEnded_ += 1;
  lastFrame_ = phasesSince(frameStart_, stats_);
  traceMsThisFrame_ = 0;
  if (now - stats_.sinceMs >= 2000) {
    if (settings_.tracer(engine_).printStats && stats_.frames > 0) printFrameStats(now);
    // The loading screen's long frames would hide the first hitches of play: frames of play only.
    if (stats_.viewFrames > 0) lastPeriodFrameMs_ = stats_.viewFramesMs / stats_.viewFrames;
    stats_ = FrameStats{};
    stats_.sinceMs = now;
    stats_.allocationsAtStart = allocationCount();
  }
}

void Module::printFrameStats(int nowMs) const {
  const FrameStats& s = stats_;
  const double n = s.frames;
  const double accounted = accountedMs(s);
  // One line of name=value pairs (per-frame means) that scripts/engine_bench.sh parses.
  engine_.print(q3abi::PRINT_ALL,
                "pathtracer: stats %s fps=%.1f frame_ms=%.2f world_views=%.2f scene_ms=%.2f commit_ms=%.2f "
                "trace_ms=%.2f temporal_ms=%.2f denoise_ms=%.2f resolve_ms=%.2f upload_ms=%.2f model_views=%.2f model_view_ms=%.2f "
                "overlay2d_ms=%.2f present_ms=%.2f engine_ms=%.2f accumulated=%u anim_ms=%.3f anim_updates=%.2f resample_ms=%.2f "
                "taau_ms=%.2f scale=%.3f allocations=%.2f wait_ms=%.2f max_frame_ms=%.1f\n",
                presetName(settings_.tracer(engine_).preset), 1000.0 * n / std::max(1, nowMs - s.sinceMs),
                s.frameMs / n, s.views / n, s.world.sceneMs / n, s.world.commitMs / n, s.world.traceMs / n,
                s.world.temporalMs / n, s.world.denoiseMs / n, s.world.resolveMs / n, s.uploadMs / n, s.modelViews / n, s.modelViewMs / n,
                s.overlay2dMs / n, s.presentMs / n, std::max(0.0, s.frameMs - accounted) / n, s.accumulated,
                s.world.animationMs / n, s.world.animationUpdates / n, s.world.resampleMs / n, s.world.taauMs / n, s.scale,
                static_cast<double>(allocationCount() - s.allocationsAtStart) / n, s.waitMs / n, s.maxFrameMs);
}

void Module::printSlowFrame(double frameMs) {
  if (stats_.slowFramesPrinted >= kSlowFramesPerPeriod) return;
  stats_.slowFramesPrinted += 1;
  const FrameStats& f = lastFrame_;
  // A pipelined world view's phases count in the frame that waited for it (the next one).
  engine_.print(q3abi::PRINT_ALL,
                "pathtracer: slow frame %llu: %.1f ms: world_views=%d scene_ms=%.1f commit_ms=%.1f trace_ms=%.1f "
                "denoise_ms=%.1f temporal_ms=%.1f model_views=%d model_view_ms=%.1f upload_ms=%.1f overlay2d_ms=%.1f "
                "present_ms=%.1f wait_ms=%.1f engine_ms=%.1f\n",
                static_cast<unsigned long long>(framesEnded_), frameMs, f.views, f.world.sceneMs, f.world.commitMs,
                f.world.traceMs, f.world.denoiseMs, f.world.temporalMs, f.modelViews, f.modelViewMs, f.uploadMs,
                f.overlay2dMs, f.presentMs, f.waitMs, std::max(0.0, frameMs - accountedMs(f)));
}

void Module::clearScene() { scene_.clear(); }

void Module::addRefEntityToScene(const q3abi::refEntity_t* entity) {
  if (entity == nullptr) return;
  if (!scene_.addEntity(*entity))
    engine_.print(q3abi::PRINT_DEVELOPER, "pathtracer: entity dropped (bad type/values or full)\n");
}

void Module::addPolyToScene(q3abi::qhandle_t shader, int numVerts, const q3abi::polyVert_t* verts,
                            int count) {
  scene_.addPolys(shader, numVerts, verts, count);
}

void Module::addLightToScene(const float* origin, float intensity, float r, float g, float b) {
  if (!settings_.dynamicLights()) return;
  scene_.addLight(origin, intensity, r, g, b, false);
}

void Module::addAdditiveLightToScene(const float* origin, float intensity, float r, float g,
                                     float b) {
  if (!settings_.dynamicLights()) return;
  scene_.addLight(origin, intensity, r, g, b, true);
}

void Module::renderScene(const q3abi::refdef_t* view) {
  if (view == nullptr || !window_.isOpen() || !frameOpen_) return;
  const bool noWorld = (view->rdflags & q3abi::RDF_NOWORLDMODEL) != 0;
  if (!noWorld && !world_) throw DropError("RenderScene: no world loaded");
  if (view->width <= 0 || view->height <= 0 || view->width > 16384 || view->height > 16384) return;
  if (!std::isfinite(view->fov_x) || !std::isfinite(view->fov_y)) return;
  TracerSettings tracer = settings_.tracer(engine_);
  if (tracer.targetFps > 0.0f) tracer.resolutionScale = resolution_.scale();
  const int start = engine_.milliseconds();
  if (!noWorld && views_ != nullptr) {
    stats_.scale = tracer.resolutionScale;
    renderWorldView(*view, tracer);
  } else if (noWorld && modelViews_ != nullptr) {
    std::optional<TracedPicture> picture;
    const Clock::time_point began = Clock::now();
    try {
      picture = modelViews_->render(*view, scene_, tracer, shaders_, models_, nullptr);
    } catch (const std::exception& error) {
      // Keep playing (2D still works); say it a few times, not every frame.
      if (renderFailures_++ < 3) engine_.warn(std::string("RenderScene: ") + error.what());
    }
    stats_.modelViews += 1;
    stats_.modelViewMs += millisecondsSince(began);
    if (picture) {
      const ScopeTimer upload(stats_.uploadMs);
      // The world view keeps texture 0; model views of the frame take the next ones in turn.
      const int slot = 1 + std::min(modelViewsThisFrame_++, Overlay2D::kViewSlots - 2);
      overlay_.drawPixels(slot, picture->rgba, picture->width, picture->height, static_cast<float>(view->x),
                          static_cast<float>(view->y), static_cast<float>(view->width),
                          static_cast<float>(view->height), false);
    }
  }
  traceMsThisFrame_ += engine_.milliseconds() - start;
  // The next view holds only what is added after this one (as in the stock renderer).
  scene_.clear();
}

void Module::renderWorldView(const q3abi::refdef_t& view, const TracerSettings& tracer) {
  const uint64_t frame = framesEnded_;
  bool secondView = false;   // a world view started earlier in this frame
  bool shown = false;        // this frame shows a world picture already
  if (views_->started()) {
    secondView = startedFrame_ == frame;
    std::optional<TracedPicture> picture = finishWorldView();
    // The view started in the last frame is what this frame shows; an older one (frames without
    // a world view between) is dropped.
    if (picture && (secondView || startedFrame_ + 1 == frame)) {
      showWorldView(startedView_, *picture);
      shown = true;
    } else if (picture) {
      shownFrame_ = UINT64_MAX;   // the dropped picture took the shown one's bytes
    }
  }
  // Pipelined only where the last frame showed a world view (this frame then shows its picture or
  // that of the view started then) and no frame must hold its own: a second world view in a frame,
  // video frames, the film for EXR screenshots.
  const bool shownLastFrame = shownFrame_ != UINT64_MAX && shownFrame_ + 1 == frame && shownPicture_.rgba != nullptr;
  const bool pipeline = tracer.pipeline && !secondView && !pendingVideo_ && !tracer.captureExr && (shown || shownLastFrame);
  if (pipeline) {
    if (!shown) {   // the first pipelined frame shows the last frame's picture again
      const ScopeTimer upload(stats_.uploadMs);
      overlay_.drawPixels(0, shownPicture_.rgba, shownPicture_.width, shownPicture_.height,
                          static_cast<float>(shownView_.x), static_cast<float>(shownView_.y),
                          static_cast<float>(shownView_.width), static_cast<float>(shownView_.height), true);
      redrawFlares(shownView_);
      shownFrame_ = frame;
    }
    try {
      views_->start(view, scene_, tracer, shaders_, models_, world_.get());
      startedView_ = view;
      startedFrame_ = frame;
    } catch (const std::exception& error) {
      if (renderFailures_++ < 3) engine_.warn(std::string("RenderScene: ") + error.what());
    }
    return;
  }
  std::optional<TracedPicture> picture;
  try {
    picture = views_->render(view, scene_, tracer, shaders_, models_, world_.get());
  } catch (const std::exception& error) {
    // Keep playing (2D still works); say it a few times, not every frame.
    if (renderFailures_++ < 3) engine_.warn(std::string("RenderScene: ") + error.what());
  }
  stats_.views += 1;
  if (!picture) return;
  countWorldView(*picture, false);
  showWorldView(view, *picture);
}

std::optional<TracedPicture> Module::finishWorldView() {
  std::optional<TracedPicture> picture;
  const Clock::time_point began = Clock::now();
  try {
    picture = views_->finish();
  } catch (const std::exception& error) {
    if (renderFailures_++ < 3) engine_.warn(std::string("RenderScene: ") + error.what());
  }
  stats_.waitMs += millisecondsSince(began);
  stats_.views += 1;
  if (picture) countWorldView(*picture, true);
  return picture;
}

void Module::countWorldView(const TracedPicture& picture, bool offThread) {
  addTimings(stats_.world, picture.timings);
  if (offThread) {
    const ViewTimings& t = picture.timings;
    stats_.offThreadMs +=
        t.commitMs + t.resampleMs + t.traceMs + t.temporalMs + t.denoiseMs + t.resolveMs + t.taauMs;
  }
  stats_.accumulated = picture.accumulatedFrames;
  if (settings_.tracer(engine_).captureExr) filmCapture_.assign(picture);
}

void Module::showWorldView(const q3abi::refdef_t& view, const TracedPicture& picture) {
  {
    const ScopeTimer upload(stats_.uploadMs);
    // The world view keeps texture 0.
    overlay_.drawPixels(0, picture.rgba, picture.width, picture.height, static_cast<float>(view.x),
                        static_cast<float>(view.y), static_cast<float>(view.width), static_cast<float>(view.height),
                        true);
  }
  drawFlares(view, picture);
  shownView_ = view;
  shownFrame_ = framesEnded_;
  shownPicture_ = picture;
}

void Module::drawFlares(const q3abi::refdef_t& view, const TracedPicture& picture) {
  if (worldFlares_.empty()) return;
  const PictureSettings settings = settings_.picture(engine_);
  if (!settings.flares) return;
  FlareView flareView;
  const ViewAxes axes = viewAxesOf(view);
  flareView.origin = axes.origin;
  flareView.forward = axes.forward;
  flareView.left = axes.left;
  flareView.up = axes.up;
  flareView.fovX = view.fov_x;
  flareView.fovY = view.fov_y;
  flareView.x = view.x;
  flareView.y = view.y;
  flareView.width = view.width;
  flareView.height = view.height;
  flareView.timeMs = view.time;
  // The depth of the traced pixel under a window position (the picture may be traced smaller).
  const auto depthAt = [&](float x, float y) {
    const int w = picture.filmWidth, h = picture.filmHeight;
    if (picture.depth.size() != size_t(w) * size_t(h) || picture.depth.empty())
      return std::numeric_limits<float>::infinity();
    const int px = std::clamp(static_cast<int>((x - view.x) * w / view.width), 0, w - 1);
    const int py = std::clamp(static_cast<int>((y - view.y) * h / view.height), 0, h - 1);
    return picture.depth[size_t(py) * size_t(w) + size_t(px)];
  };
  flareTracker_.update(flareView, worldFlares_, settings.flare, depthAt, flareQuads_);
  redrawFlares(view);
}

void Module::redrawFlares(const q3abi::refdef_t& view) {
  if (flareQuads_.empty() || worldFlares_.empty() || !settings_.picture(engine_).flares) return;
  const ImageSource images = [this](const std::string& name) { return images_.load(engine_, name); };
  const double shaderSeconds = view.time * 0.001;
  overlay_.clip(view.x, view.y, view.width, view.height);
  for (const FlareQuad& quad : flareQuads_) {
    const float color[4] = {quad.color.r, quad.color.g, quad.color.b, 1.0f};
    overlay_.setColor(color);
    // Texture t runs up the screen, as stock's window-space quad has it.
    overlay_.drawPic(shaders_, engine_, images, flareShader_, shaderSeconds, quad.centerX - quad.halfSize,
                     quad.centerY - quad.halfSize, 2.0f * quad.halfSize, 2.0f * quad.halfSize, 0.0f, 1.0f, 1.0f, 0.0f);
  }
  overlay_.setColor(nullptr);
  overlay_.clearClip();
}

void Module::setColor(const float* rgba) { overlay_.setColor(rgba); }

void Module::drawStretchPic(float x, float y, float w, float h, float s1, float t1, float s2,
                            float t2, q3abi::qhandle_t shader) {
  if (!frameOpen_ || !finiteRect(x, y, w, h) || !finiteRect(s1, t1, s2, t2)) return;
  const ScopeTimer timer(stats_.overlay2dMs);
  const ImageSource images = [this](const std::string& name) { return images_.load(engine_, name); };
  overlay_.drawPic(shaders_, engine_, images, shader, seconds(), x, y, w, h, s1, t1, s2, t2);
}

void Module::drawStretchRaw(int x, int y, int w, int h, int cols, int rows,
                            const q3abi::byte* data, int client, bool dirty) {
  if (!frameOpen_) return;
  if (cols <= 0 || rows <= 0 || cols > 4096 || rows > 4096) return;
  const ScopeTimer timer(stats_.overlay2dMs);
  if (dirty && data != nullptr) overlay_.uploadRaw(client, data, cols, rows);
  overlay_.drawRaw(client, static_cast<float>(x), static_cast<float>(y), static_cast<float>(w),
                   static_cast<float>(h));
}

void Module::uploadCinematic(int /*w*/, int /*h*/, int cols, int rows, const q3abi::byte* data,
                             int client, bool dirty) {
  if (!window_.isOpen() || cols <= 0 || rows <= 0 || cols > 4096 || rows > 4096) return;
  if (dirty && data != nullptr) overlay_.uploadRaw(client, data, cols, rows);
}

}  // namespace glue

namespace glue {

int Module::lightForPoint(float* point, float* ambient, float* directed, float* direction) {
  if (point == nullptr || ambient == nullptr || directed == nullptr || direction == nullptr)
    return 0;
  if (!world_) return 0;
  return world_->lightForPoint(point, ambient, directed, direction) ? 1 : 0;
}

int Module::markFragments(int numPoints, const q3abi::vec3_t* points, const float* projection,
                          int maxPoints, float* pointBuffer, int maxFragments,
                          q3abi::markFragment_t* fragments) {
  if (!world_ || points == nullptr || projection == nullptr || pointBuffer == nullptr ||
      fragments == nullptr || numPoints < 3 || maxPoints <= 0 || maxFragments <= 0)
    return 0;
  return world_->markFragments(numPoints, points, projection, maxPoints, pointBuffer,
                               maxFragments, fragments);
}

bool Module::inPVS(const float* p1, const float* p2) {
  if (p1 == nullptr || p2 == nullptr) return false;
  if (!world_) return true;   // nothing known: everything may be visible
  return world_->inPVS(p1, p2);
}

}  // namespace glue
