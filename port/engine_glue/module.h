#pragma once
// The renderer module's one state object: created by GetRefAPI, destroyed by Shutdown(1) or
// dlclose. Every refexport_t entry point lands on a method of Module (see module_entry.cpp).
#include <chrono>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "port/engine_glue/capture_exr.h"
#include "port/engine_glue/dynamic_resolution.h"
#include "port/engine_glue/engine.h"
#include "port/engine_glue/images.h"
#include "port/engine_glue/ioq3_abi.h"
#include "port/engine_glue/models.h"
#include "port/engine_glue/overlay2d.h"
#include "port/engine_glue/scene.h"
#include "port/engine_glue/settings.h"
#include "port/engine_glue/shader_scripts.h"
#include "port/engine_glue/shaders.h"
#include "port/engine_glue/views.h"
#include "port/engine_glue/window.h"
#include "port/engine_glue/world.h"

namespace glue {

class ViewRenderer;

/// rand() draws stock opengl1 makes when it starts (its noise lattice); BeginRegistration makes
/// as many, so that the game's random sequence runs as under opengl1 (module.cpp).
inline constexpr int kStockRendererStartDraws = 512;

/// A screenshot asked for by a console command, taken at the end of the frame.
struct ScreenshotRequest {
  std::string extension;   ///< "tga", "jpg" or "png"
  std::string fileName;    ///< explicit name, or empty for the next free shots number
  bool silent = false;
  bool levelshot = false;
};

/// A TakeVideoFrame call, served at the end of the frame (buffers belong to the engine).
struct VideoFrameRequest {
  int width = 0;
  int height = 0;
  q3abi::byte* encodeBuffer = nullptr;
  bool motionJpeg = false;
};

/// Frame timing gathered for r_pt_stats: sums over the frames since `sinceMs`, in milliseconds.
struct FrameStats {
  int sinceMs = 0;
  int frames = 0;
  int views = 0;               ///< World views traced.
  int modelViews = 0;          ///< Views without the world (HUD heads, 3D icons, menu models).
  ViewTimings world;           ///< The world views' phases.
  double uploadMs = 0.0;       ///< Traced pictures into GL textures (all views).
  double modelViewMs = 0.0;    ///< Views without the world, all of their phases.
  double overlay2dMs = 0.0;    ///< 2D calls (DrawStretchPic, DrawStretchRaw, cinematics).
  double presentMs = 0.0;      ///< Screenshots, video frames and the buffer swap.
  /// World views traced while the game went on (r_pt_pipeline): their scene set-up is on the
  /// game's thread, the rest (`world` but sceneMs) on the renderer's, and waitMs is how long the
  /// game's thread waited for them.
  double offThreadMs = 0.0;
  double waitMs = 0.0;         ///< See offThreadMs.
  double frameMs = 0.0;        ///< BeginFrame to BeginFrame of the next frame (engine and game included).
  double maxFrameMs = 0.0;     ///< The longest of those frames.
  double viewFramesMs = 0.0;   ///< frameMs of the frames that finished a world view (not loading screens).
  int viewFrames = 0;          ///< Those frames.
  int slowFramesPrinted = 0;   ///< Frames over kSlowFrameMs described this period (r_pt_stats).
  uint32_t accumulated = 0;    ///< Frames in the last world view's picture.
  float scale = 0.0f;          ///< r_pt_scale of the last world view (dynamic resolution's choice with r_pt_fps).
  uint64_t allocationsAtStart = 0;   ///< allocationCount() when the period began.
};

/// All of the renderer's state.
class Module {
 public:
  explicit Module(const q3abi::refimport_t& ri);
  ~Module();
  Module(const Module&) = delete;
  Module& operator=(const Module&) = delete;

  // ---- refexport_t, in the engine's order ----
  void shutdown(bool destroyWindow);
  void beginRegistration(q3abi::glconfig_t* config);
  q3abi::qhandle_t registerModel(const char* name);
  q3abi::qhandle_t registerSkin(const char* name);
  q3abi::qhandle_t registerShader(const char* name);
  q3abi::qhandle_t registerShaderNoMip(const char* name);
  void loadWorld(const char* name);
  void setWorldVisData(const q3abi::byte* vis);
  void endRegistration();
  void clearScene();
  void addRefEntityToScene(const q3abi::refEntity_t* entity);
  void addPolyToScene(q3abi::qhandle_t shader, int numVerts, const q3abi::polyVert_t* verts,
                      int count);
  int lightForPoint(float* point, float* ambient, float* directed, float* direction);
  void addLightToScene(const float* origin, float intensity, float r, float g, float b);
  void addAdditiveLightToScene(const float* origin, float intensity, float r, float g, float b);
  void renderScene(const q3abi::refdef_t* view);
  void setColor(const float* rgba);
  void drawStretchPic(float x, float y, float w, float h, float s1, float t1, float s2, float t2,
                      q3abi::qhandle_t shader);
  void drawStretchRaw(int x, int y, int w, int h, int cols, int rows, const q3abi::byte* data,
                      int client, bool dirty);
  void uploadCinematic(int w, int h, int cols, int rows, const q3abi::byte* data, int client,
                       bool dirty);
  void beginFrame(int stereoFrame);
  void endFrame(int* frontEndMsec, int* backEndMsec);
  int markFragments(int numPoints, const q3abi::vec3_t* points, const float* projection,
                    int maxPoints, float* pointBuffer, int maxFragments,
                    q3abi::markFragment_t* fragments);
  int lerpTag(q3abi::orientation_t* tag, q3abi::qhandle_t model, int startFrame, int endFrame,
              float frac, const char* tagName);
  void modelBounds(q3abi::qhandle_t model, float* mins, float* maxs);
  void registerFont(const char* fontName, int pointSize, q3abi::fontInfo_t* font);
  void remapShader(const char* oldShader, const char* newShader, const char* timeOffset);
  bool getEntityToken(char* buffer, int size);
  bool inPVS(const float* p1, const float* p2);
  void takeVideoFrame(int width, int height, q3abi::byte* captureBuffer,
                      q3abi::byte* encodeBuffer, bool motionJpeg);

  // ---- console commands ----
  /// screenshot / screenshotJPEG / screenshotPNG [silent | levelshot | NAME].
  void screenshotCommand(const char* extension);
  /// pt_allocations [trace N]: prints the module's heap allocations and frames since the last
  /// call; `trace N` also prints a backtrace of each of the next N allocations.
  void allocationsCommand();

  /// The engine services (for the entry points' error reporting).
  const Engine& engine() const { return engine_; }

 private:
  void ensureWindow(q3abi::glconfig_t* config);
  /// Recomputes the display's gamma ramp from r_gamma.
  void updateDisplayRamp();
  /// Prints the r_pt_stats line: per-frame means of stats_ up to `nowMs`.
  void printFrameStats(int nowMs) const;
  /// Prints a slow frame of `frameMs` with its phases (lastFrame_), r_pt_stats on.
  void printSlowFrame(double frameMs);
  double seconds() const;
  /// The stock picture cvars with the window's fullscreen state (the display's overbright bits).
  PictureSettings picture() const;
  void takeScreenshot(const ScreenshotRequest& request);
  void captureVideoFrame(const VideoFrameRequest& request);
  std::string nextScreenshotName(const std::string& extension);
  void fillFallbackFont(q3abi::fontInfo_t& font, int pointSize);
  void addCommands();
  void removeCommands();
  /// r_flares: the map's flares over a traced view of the world, tested against its depth and
  /// drawn with the flare shader (flares.h).
  void drawFlares(const q3abi::refdef_t& view, const TracedPicture& picture);
  /// The flare quads of the last drawFlares again (a world picture shown a second time).
  void redrawFlares(const q3abi::refdef_t& view);
  /// A view of the world: traced in this frame, or (r_pt_pipeline) started here and shown in the next.
  void renderWorldView(const q3abi::refdef_t& view, const TracerSettings& tracer);
  /// The picture of the world view started last (waiting for it); counts its time in stats_.
  std::optional<TracedPicture> finishWorldView();
  /// Counts a world view's phases in stats_ (`offThread`: traced while the game went on).
  void countWorldView(const TracedPicture& picture, bool offThread);
  /// Draws a world view's picture and its flares; it is the frame's shown world view.
  void showWorldView(const q3abi::refdef_t& view, const TracedPicture& picture);

  Engine engine_;
  Settings settings_;
  Window window_;
  q3abi::glconfig_t glconfig_{};
  Overlay2D overlay_;
  ImageCache images_;
  ShaderScripts scripts_;
  ShaderRegistry shaders_;
  ModelRegistry models_;
  std::unordered_map<std::string, q3abi::fontInfo_t> fonts_;
  std::unique_ptr<World> world_;
  SceneFrame scene_;
  std::unique_ptr<ViewRenderer> views_;        ///< Views of the world: its scene, film and history.
  /// Views without the world (RDF_NOWORLDMODEL: HUD heads, 3D icons, menu models): a scene and
  /// film of their own, so that they never rebuild, resize or reset the world view's.
  std::unique_ptr<ViewRenderer> modelViews_;
  std::vector<Flare> worldFlares_;      ///< The world model's flare surfaces.
  FlareTracker flareTracker_;           ///< Their fade state from view to view of the world.
  std::vector<FlareQuad> flareQuads_;   ///< This view's flare quads (capacity kept).
  q3abi::qhandle_t flareShader_ = 0;    ///< "flareShader", registered with the world.
  /// r_pt_pipeline: the world view started (traced while the game goes on) and its frame.
  q3abi::refdef_t startedView_{};
  uint64_t startedFrame_ = 0;
  /// The world view shown last, its frame, and its picture (rgba valid until views_ hands out
  /// another picture: a started view does not touch it).
  q3abi::refdef_t shownView_{};
  uint64_t shownFrame_ = UINT64_MAX;
  TracedPicture shownPicture_;
  std::vector<ScreenshotRequest> pendingShots_;
  FilmCapture filmCapture_;   ///< r_pt_captureExr: the last world view of the last frame, for screenshots.
  /// The display's gamma ramp (r_gamma; stock sets it on the display, we map the finished frame).
  std::array<uint8_t, 256> displayRamp_{};
  bool rampIsIdentity_ = true;
  std::optional<VideoFrameRequest> pendingVideo_;
  bool registered_ = false;        ///< Between BeginRegistration and Shutdown.
  bool commandsAdded_ = false;
  bool frameOpen_ = false;         ///< Between BeginFrame and EndFrame.
  int lastShotNumber_ = 0;
  int renderFailures_ = 0;
  int traceMsThisFrame_ = 0;
  int modelViewsThisFrame_ = 0;    ///< Views without the world drawn since BeginFrame.
  FrameStats stats_;
  FrameStats frameStart_;   ///< stats_ at the last BeginFrame: this frame's phases are what it gained since.
  FrameStats lastFrame_;    ///< The last ended frame's phases (its frameMs known at the next BeginFrame).
  double lastPeriodFrameMs_ = 0.0;   ///< The mean frame with a world view of the last period that had one (0: none yet).
  uint64_t framesEnded_ = 0;                ///< EndFrames since the module was loaded.
  uint64_t allocationsMark_ = 0;            ///< allocationCount() at the last pt_allocations.
  uint64_t framesMark_ = 0;                 ///< framesEnded_ at the last pt_allocations.
  int frameStartMs_ = 0;
  std::chrono::steady_clock::time_point frameBegan_{};   ///< Last BeginFrame (r_pt_stats).
  ResolutionController resolution_;   ///< r_pt_fps: the world views' resolution scale.
};

}  // namespace glue
