#pragma once
// One pa-render invocation of a map and what it left behind: PNG, EXR depth, --stats JSON.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/all_maps_render/contact_sheet.h"

namespace pa::allmaps {

/// One integrator of a request.
struct IntegratorRequest {
  std::string name;                  ///< "lightmap", "direct" or "path".
  uint32_t samplesPerPixel = 4;
};

/// What to render: the integrators in order, by one pa-render process over the map loaded once.
struct RenderRequest {
  std::filesystem::path paRender;    ///< The pa-render executable.
  std::filesystem::path scene;       ///< GAMEDIR/maps/NAME.bsp (resolved by pa-render's .bsp importer).
  std::vector<IntegratorRequest> integrators;
  std::string tonemap;               ///< "clamp", "aces" or "reinhard".
  uint32_t camera = 0;               ///< --camera index.
  /// --exposure: a gain, or "auto": the first integrator's picture metered, its gain for all.
  std::string exposure = "1";
  uint32_t width = 160;
  uint32_t height = 90;
  uint32_t threads = 0;              ///< 0 = pa-render's default (all cores).
  /// Writes STEM.log, and per integrator STEM_NAME.{png,exr,json} (STEM.* for a single one).
  std::filesystem::path outputStem;
  bool reuseExisting = false;        ///< Read the files an earlier run with these settings left instead of rendering.
  std::vector<std::string> extraArguments;   ///< Appended to pa-render's command line (tests: --light-scale).
};

/// What came back for one integrator.
struct RenderResult {
  int exitCode = -1;                 ///< pa-render's exit status (-1: did not run / killed).
  std::string log;                   ///< Its stderr (warnings, summaries or error message).
  double wallMilliseconds = 0.0;     ///< Load (first integrator only) + render, from --stats.
  double renderMilliseconds = 0.0;   ///< Render only (from --stats).
  std::string cameraName;            ///< Camera pa-render reports having used.
  uint64_t triangles = 0;
  uint64_t lights = 0;
  double exposure = 1.0;             ///< Gain pa-render applied (metered with "auto").
  bool exposureAtMaxGain = false;    ///< "auto": the metered gain hit its upper clamp.
  RgbaImage image;                   ///< The PNG.
  RgbaImage unexposedImage;          ///< The EXR's radiance at exposure 1, clamp, sRGB (the stock look).
  std::vector<float> depth;          ///< The EXR Z channel (inf = sky/nothing).
  std::string error;                 ///< Non-empty when something above could not be obtained.
  /// True when the render ran and every output was read back.
  bool ok() const { return error.empty(); }
};

/// Runs pa-render (quiet, fixed seed) and reads its outputs back (or only reads them, with
/// reuseExisting when every --stats JSON says they were made with the same settings); one result
/// per integrator, in order. An integrator whose outputs were written counts as rendered even
/// when a later one failed. Never throws for a failed render: the reason is in `error` (and `log`).
std::vector<RenderResult> runPaRender(const RenderRequest& request);

/// The channel `name` of a single-part scanline OpenEXR, as floats; throws std::runtime_error
/// naming the file when it cannot be read or has no such channel.
std::vector<float> readExrChannel(const std::filesystem::path& path, const std::string& name, uint32_t& width,
                                  uint32_t& height);

}  // namespace pa::allmaps
