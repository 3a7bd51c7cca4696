#pragma once
// Command line of pa-render: parsing (pure, unit-tested) and the --help text.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "renderer/scene/scene_types.h"

namespace pa::cli {

/// One integrator of a run and its samples per pixel per frame (0: --spp).
struct IntegratorPass {
  Integrator integrator = Integrator::Path;
  uint32_t samplesPerPixel = 0;
};

/// Everything pa-render was asked to do.
struct CliOptions {
  std::filesystem::path scene;                  ///< Input scene (importer chosen by extension).
  std::filesystem::path pngOut;                 ///< Tonemapped 8-bit image (-o).
  std::optional<std::filesystem::path> exrOut;  ///< Linear radiance + AOV layers (--exr).
  std::optional<std::filesystem::path> statsOut;  ///< Machine-readable summary as JSON (--stats).
  uint32_t width = 0;                           ///< 0 = derived (see usage text).
  uint32_t height = 0;
  uint32_t samplesPerPixel = 16;                ///< Per frame.
  uint32_t frames = 1;                          ///< Frames accumulated into the image.
  uint32_t bounces = 4;
  uint32_t rouletteStart = 3;                   ///< Scatterings before Russian roulette (--roulette-start).
  uint32_t seed = 0;
  uint32_t threads = 0;                         ///< 0 = all cores.
  /// --integrator: rendered in this order over one loaded scene; with more than one, each output
  /// file name gets "_NAME" before its extension (outputPathFor).
  std::vector<IntegratorPass> integrators{IntegratorPass{}};
  Tonemap tonemap = Tonemap::AcesFitted;        ///< Display transform of the PNG.
  LightingLook lighting = LightingLook::Physical;   ///< How the PNG shows reflected light.
  uint32_t camera = 0;                          ///< Index into the scene's cameras.
  float clamp = 0.0f;                           ///< Radiance clamp per path, 0 = off.
  float exposure = 1.0f;                        ///< Fixed gain; ignored with autoExposure.
  bool autoExposure = false;                    ///< --exposure auto: gain metered on the image (film/auto_exposure.h).
  float lightScale = 1.0f;                      ///< Photometric -> renderer units (glTF lights, emitters).
  bool progress = false;                        ///< Force the progress bar even when stderr is not a TTY.
  bool quiet = false;                           ///< No progress bar and no warnings; summary only.
  bool denoise = false;                         ///< Filter the image with the à-trous denoiser (--denoise).
  bool spreadFireflies = false;                 ///< --spread-fireflies (denoise/fireflies.h).
  bool cameraPackets = true;                    ///< Camera rays in 4x4 packets (off: --no-camera-packets).
  bool lampVisibility = true;                   ///< RendererConfig::lampVisibility (off: --no-lamp-visibility).
  bool restir = false;                          ///< Reservoir resampling of direct light (--restir).
  bool temporalGradients = true;                ///< Temporal gradients with --play temporal (--no-temporal-gradients).
  bool bakedPathEnd = false;                    ///< Paths end on the bake's light (--baked-path-end).
  /// How the frames combine (--play): accumulate into one mean; or play them as the game does
  /// (a new seed each, no accumulation), on their own or with temporal accumulation.
  enum class Play : uint8_t { Accumulate, Independent, Temporal } play = Play::Accumulate;
};

/// Outcome of parsing.
enum class ParseStatus : uint8_t {
  Ok,     ///< options is filled.
  Help,   ///< --help was given: print usageText() and exit 0.
  Error,  ///< message says what is wrong: print it and exit 2.
};

/// Result of parseCommandLine.
struct ParseResult {
  ParseStatus status = ParseStatus::Error;
  CliOptions options;
  std::string message;
};

/// Parses arguments (without the program name). Accepts "--opt value" and "--opt=value".
ParseResult parseCommandLine(std::span<const std::string_view> args);

/// The full --help text.
std::string usageText(std::string_view program);

/// Integrator name as on the command line ("lightmap", "direct", "path").
std::string_view integratorName(Integrator integrator);

/// Samples per pixel per frame of a pass: its own, else --spp.
uint32_t samplesPerPixelOf(const CliOptions& options, const IntegratorPass& pass);

/// An output file of one pass: path itself for a run of one integrator, else path with "_NAME"
/// before its extension (out.png -> out_direct.png).
std::filesystem::path outputPathFor(const std::filesystem::path& path, const CliOptions& options, Integrator integrator);

/// Tonemap name as on the command line ("aces", "reinhard", "clamp").
std::string_view tonemapName(Tonemap tonemap);

}  // namespace pa::cli
