// Import -> commit -> for each integrator: F x render(N spp) -> PNG (+ EXR, stats), with progress
// and a summary line.
#include "renderer/cli/render_job.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "renderer/cli/image_output.h"
#include "renderer/cli/progress.h"
#include "renderer/cli/scene_importer.h"
#include "renderer/scene/film/auto_exposure.h"
#include "renderer/scene/film/film.h"
#include "renderer/scene/renderer.h"

namespace pa::cli {
namespace {

constexpr uint32_t kDefaultWidth = 640;
constexpr float kDefaultAspect = 16.0f / 9.0f;

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string knownExtensions() {
  std::string list;
  for (const auto& importer : sceneImporters())
    for (std::string_view extension : importer->extensions()) {
      if (!list.empty()) list += ' ';
      list += extension;
    }
  return list;
}

/// Fraction of pixels whose first hit is the sky or nothing (depth not finite).
double skyFraction(std::span<const float> depth) {
  if (depth.empty()) return 0.0;
  const auto sky = std::count_if(depth.begin(), depth.end(), [](float d) { return !std::isfinite(d); });
  return static_cast<double>(sky) / static_cast<double>(depth.size());
}

/// The --stats record of a metered exposure (settings included, so scripts need no constants).
nlohmann::json autoExposureJson(const AutoExposure& metered) {
  const AutoExposureSettings settings;
  const char* clamped = metered.clamped == ExposureClamp::Max   ? "max"
                        : metered.clamped == ExposureClamp::Min ? "min"
                                                                : "none";
  return {{"gain", metered.gain},
          {"key", metered.key},
          {"metered_pixels", metered.meteredPixels},
          {"metered_sky", metered.meteredSky},
          {"clamped", clamped},
          {"target_key", settings.targetKey},
          {"black_level", settings.blackLevel},
          {"min_gain", settings.minGain},
          {"max_gain", settings.maxGain}};
}

/// Writes the --stats JSON; throws std::runtime_error when the file cannot be written.
void writeStats(const std::filesystem::path& path, const nlohmann::json& stats) {
  if (const std::filesystem::path parent = path.parent_path(); !parent.empty()) {
    std::error_code error;
    std::filesystem::create_directories(parent, error);
  }
  std::ofstream out(path);
  out << stats.dump(2) << '\n';
  if (!out.flush()) throw std::runtime_error(path.string() + ": cannot write stats");
}

/// What renderPass measured, and its last frame.
struct PassOutcome {
  FrameView frame;
  double resampleMs = 0.0, traceMs = 0.0;   ///< Summed over the frames.
  double renderSeconds = 0.0, firstFrameSeconds = 0.0;
  std::optional<double> frameChange;   ///< Played frames: mean change of display luma, last pairs.
};

/// Renders options.frames frames of one integrator with a progress bar.
PassOutcome renderPass(Renderer& renderer, const Camera& view, RenderSettings settings, const CliOptions& options,
                       std::FILE* log) {
  const bool showProgress = !options.quiet && (options.progress || ::isatty(::fileno(log)));
  ProgressBar progress(options.frames, showProgress, log);
  progress.update(0);
  PassOutcome outcome;
  // Frame-to-frame change of display luma (played frames only), over the last kChangePairs pairs.
  constexpr uint32_t kChangePairs = 8;
  std::vector<uint8_t> previousRgba8;
  double changeSum = 0.0;
  uint64_t changeCount = 0;
  for (uint32_t f = 0; f < options.frames; ++f) {
    if (!settings.accumulate) settings.seed = options.seed + f;
    outcome.frame = renderer.render(view, settings);
    const FrameView& frame = outcome.frame;
    outcome.resampleMs += frame.timings.resampleMs;
    outcome.traceMs += frame.timings.traceMs;
    if (!settings.accumulate && f + kChangePairs >= options.frames) {
      if (!previousRgba8.empty()) {
        for (size_t i = 0; i + 3 < frame.rgba8.size(); i += 4) {
          const auto luma = [](const uint8_t* p) { return (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) / 255.0; };
          changeSum += std::abs(luma(&frame.rgba8[i]) - luma(&previousRgba8[i]));
          ++changeCount;
        }
      }
      previousRgba8.assign(frame.rgba8.begin(), frame.rgba8.end());
    }
    progress.update(f + 1);
    if (f == 0) outcome.firstFrameSeconds = progress.elapsedSeconds();
  }
  progress.finish();
  outcome.renderSeconds = progress.elapsedSeconds();
  if (changeCount > 0) outcome.frameChange = changeSum / static_cast<double>(changeCount);
  return outcome;
}

}  // namespace

void resolveImageSize(const CliOptions& options, float cameraAspect, uint32_t& width, uint32_t& height) {
  const float aspect = cameraAspect > 0.0f && std::isfinite(cameraAspect) ? cameraAspect : kDefaultAspect;
  auto side = [](float value) { return static_cast<uint32_t>(std::clamp(std::lround(value), 1l, 16384l)); };
  width = options.width;
  height = options.height;
  if (width == 0 && height == 0) width = kDefaultWidth;
  if (height == 0) height = side(static_cast<float>(width) / aspect);
  if (width == 0) width = side(static_cast<float>(height) * aspect);
}

int runRenderJob(const CliOptions& options, std::FILE* log) {
  const SceneImporter* importer = findImporter(options.scene);
  if (!importer) {
    std::fprintf(log, "pa-render: %s: unknown scene format \"%s\" (known: %s)\n", options.scene.string().c_str(),
                 options.scene.extension().string().c_str(), knownExtensions().c_str());
    return kExitUsage;
  }
  try {
    const auto loadStart = std::chrono::steady_clock::now();
    RendererConfig config;
    config.threads = options.threads;
    config.lampVisibility = options.lampVisibility;
    Renderer renderer(config);
    ImportOptions importOptions;
    importOptions.lightScale = options.lightScale;
    const ImportedScene scene = importer->load(options.scene, renderer, importOptions);
    if (!options.quiet)
      for (const std::string& warning : scene.warnings) std::fprintf(log, "pa-render: warning: %s\n", warning.c_str());

    ImportedCamera camera;
    if (scene.cameras.empty()) {
      if (options.camera != 0) {
        std::fprintf(log, "pa-render: %s: --camera %u requested but the scene has no cameras\n",
                     options.scene.string().c_str(), options.camera);
        return kExitFailure;
      }
      camera = framingCamera(scene);
      if (!options.quiet) std::fprintf(log, "pa-render: the scene has no camera; framing the whole scene\n");
    } else if (options.camera >= scene.cameras.size()) {
      std::fprintf(log, "pa-render: %s: --camera %u out of range (the scene has %zu cameras)\n",
                   options.scene.string().c_str(), options.camera, scene.cameras.size());
      return kExitFailure;
    } else {
      camera = scene.cameras[options.camera];
    }
    renderer.commit();
    const double loadSeconds = secondsSince(loadStart);

    RenderSettings settings;
    resolveImageSize(options, camera.aspectRatio, settings.width, settings.height);
    settings.maxBounces = options.bounces;
    settings.rouletteStart = options.rouletteStart;
    settings.radianceClamp = options.clamp;
    settings.seed = options.seed;
    settings.accumulate = options.play == CliOptions::Play::Accumulate;
    settings.temporal = options.play == CliOptions::Play::Temporal;
    settings.tonemap = options.tonemap;
    settings.lightingLook = options.lighting;
    settings.denoise = options.denoise;
    settings.spreadFireflies = options.spreadFireflies;
    settings.cameraPackets = options.cameraPackets;
    settings.restir = options.restir;
    settings.temporalGradients = options.temporalGradients;
    settings.bakedLightAtPathEnd = options.bakedPathEnd;
    settings.motionVectors = false;   // no output reads them
    settings.normalAov = options.exrOut.has_value();   // the EXR's normal layer
    settings.surfaceAovs = options.exrOut.has_value();   // its albedo and normal layers
    const Camera view = toRendererCamera(camera, static_cast<float>(settings.width) / settings.height);

    // --exposure auto meters the first pass; the later ones are exposed with its gain.
    std::optional<AutoExposure> firstMetered;
    for (size_t p = 0; p < options.integrators.size(); ++p) {
      const IntegratorPass& pass = options.integrators[p];
      if (p > 0) renderer.forgetFrames();   // each pass as a run of its own would render it
      settings.integrator = pass.integrator;
      settings.samplesPerPixel = samplesPerPixelOf(options, pass);
      settings.exposure = !options.autoExposure ? options.exposure : firstMetered ? firstMetered->gain : 1.0f;
      const PassOutcome outcome = renderPass(renderer, view, settings, options, log);
      const FrameView& frame = outcome.frame;

      // --exposure auto, first pass: meter the final (linear, possibly denoised) image and encode
      // it again with the metered gain; the EXR stays unexposed either way.
      std::optional<AutoExposure> metered;
      std::vector<uint8_t> exposedRgba8;
      std::span<const uint8_t> displayRgba8 = frame.rgba8;
      if (options.autoExposure && !firstMetered) {
        metered = meterAutoExposure(frame.radiance, frame.depth, AutoExposureSettings{});
        exposedRgba8.resize(frame.rgba8.size());
        encodeDisplay(frame.radiance, metered->gain, options.tonemap, exposedRgba8);
        displayRgba8 = exposedRgba8;
        firstMetered = metered;
      }
      const float exposure = metered ? metered->gain : settings.exposure;
      const std::filesystem::path pngOut = outputPathFor(options.pngOut, options, pass.integrator);
      writePng(pngOut, frame.width, frame.height, displayRgba8);
      std::optional<std::filesystem::path> exrOut;
      if (options.exrOut) {
        exrOut = outputPathFor(*options.exrOut, options, pass.integrator);
        ExrLayers layers{frame.width, frame.height, frame.radiance, frame.albedo, frame.normal, frame.depth, frame.variance};
        writeExr(*exrOut, layers);
      }
      if (options.statsOut) {
        nlohmann::json autoExposure = nullptr;
        if (options.autoExposure) {
          autoExposure = autoExposureJson(*firstMetered);
          autoExposure["metered_on"] = integratorName(options.integrators.front().integrator);
        }
        nlohmann::json stats = {
            {"scene", options.scene.string()},
            {"camera_index", scene.cameras.empty() ? nlohmann::json(nullptr) : nlohmann::json(options.camera)},
            {"camera", camera.name},
            {"triangles", scene.triangles},
            {"lights", scene.lights},
            {"width", settings.width},
            {"height", settings.height},
            {"integrator", integratorName(pass.integrator)},
            {"tonemap", tonemapName(options.tonemap)},
            {"denoise", options.denoise},
            {"restir", options.restir},
            {"baked_path_end", options.bakedPathEnd},
            {"resample_seconds", outcome.resampleMs / 1000.0},
            {"trace_seconds", outcome.traceMs / 1000.0},
            {"exposure", exposure},
            {"auto_exposure", autoExposure},
            {"spp", settings.samplesPerPixel},
            {"frames", options.frames},
            {"play", options.play == CliOptions::Play::Accumulate ? "accumulate"
                     : options.play == CliOptions::Play::Independent ? "independent" : "temporal"},
            {"frame_change", outcome.frameChange ? nlohmann::json(*outcome.frameChange) : nlohmann::json(nullptr)},
            {"load_seconds", loadSeconds},
            {"render_seconds", outcome.renderSeconds},
            {"first_frame_seconds", outcome.firstFrameSeconds},
            {"sky_fraction", skyFraction(frame.depth)},
            {"warnings", scene.warnings.size()},
        };
        writeStats(outputPathFor(*options.statsOut, options, pass.integrator), stats);
      }
      const double samples =
          static_cast<double>(settings.width) * settings.height * settings.samplesPerPixel * options.frames;
      std::fprintf(log,
                   "pa-render: %s: %zu triangles, %zu lights, camera \"%s\" | %ux%u, %s (%u bounces), %u frame(s) x %u spp"
                   " | %sexposure %.3g | load %s, render %s (%.2f Msamples/s) | wrote %s%s%s\n",
                   options.scene.filename().string().c_str(), scene.triangles, scene.lights, camera.name.c_str(),
                   settings.width, settings.height, std::string(integratorName(pass.integrator)).c_str(),
                   options.bounces, options.frames, settings.samplesPerPixel, options.autoExposure ? "auto " : "",
                   exposure, formatDuration(loadSeconds).c_str(), formatDuration(outcome.renderSeconds).c_str(),
                   samples / std::max(outcome.renderSeconds, 1e-9) * 1e-6, pngOut.string().c_str(),
                   exrOut ? " and " : "", exrOut ? exrOut->string().c_str() : "");
    }
    return kExitOk;
  } catch (const std::exception& e) {
    std::fprintf(log, "pa-render: error: %s\n", e.what());
    return kExitFailure;
  }
}

}  // namespace pa::cli
