// pa-render command-line parsing: every value is range-checked with a message naming the option.
#include "renderer/cli/cli_options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>
#include <limits>
#include <vector>

namespace pa::cli {
namespace {

constexpr uint32_t kMaxImageSide = 16384;

/// Parses an unsigned integer in [lo, hi]; false with a message otherwise.
bool parseUnsigned(std::string_view option, std::string_view text, uint32_t lo, uint32_t hi, uint32_t& out,
                   std::string& message) {
  uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < lo || value > hi) {
    message = std::string(option) + ": expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
              "], got \"" + std::string(text) + "\"";
    return false;
  }
  out = static_cast<uint32_t>(value);
  return true;
}

/// Parses a finite float >= lo (> lo when exclusive).
bool parseFloat(std::string_view option, std::string_view text, float lo, bool exclusive, float& out,
                std::string& message) {
  float value = 0.0f;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  const bool inRange = exclusive ? value > lo : value >= lo;
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value) || !inRange) {
    message = std::string(option) + ": expected a number " + (exclusive ? "> " : ">= ") + std::to_string(lo) +
              ", got \"" + std::string(text) + "\"";
    return false;
  }
  out = value;
  return true;
}

/// The integrators --integrator names (by integratorName).
constexpr Integrator kIntegrators[] = {Integrator::Lightmap, Integrator::Direct, Integrator::Path};

/// Parses --integrator's "NAME[:SPP][,NAME[:SPP]...]": each of lightmap, direct, path at most once.
bool parseIntegrators(std::string_view text, std::vector<IntegratorPass>& out, std::string& message) {
  std::vector<IntegratorPass> passes;
  size_t start = 0;
  while (true) {
    const size_t end = std::min(text.find(',', start), text.size());
    std::string_view item = text.substr(start, end - start);
    IntegratorPass pass;
    if (const size_t colon = item.find(':'); colon != std::string_view::npos) {
      if (!parseUnsigned("--integrator " + std::string(item.substr(0, colon)) + ":SPP", item.substr(colon + 1), 1,
                         1u << 20, pass.samplesPerPixel, message))
        return false;
      item = item.substr(0, colon);
    }
    const Integrator* named = std::find_if(std::begin(kIntegrators), std::end(kIntegrators),
                                           [&](Integrator i) { return integratorName(i) == item; });
    if (named == std::end(kIntegrators)) {
      message = "--integrator: expected lightmap, direct or path, got \"" + std::string(item) + "\"";
      return false;
    }
    pass.integrator = *named;
    for (const IntegratorPass& earlier : passes)
      if (earlier.integrator == pass.integrator) {
        message = "--integrator: " + std::string(item) + " given twice";
        return false;
      }
    passes.push_back(pass);
    if (end == text.size()) break;
    start = end + 1;
  }
  out = std::move(passes);
  return true;
}

}  // namespace

uint32_t samplesPerPixelOf(const CliOptions& options, const IntegratorPass& pass) {
  return pass.samplesPerPixel != 0 ? pass.samplesPerPixel : options.samplesPerPixel;
}

std::filesystem::path outputPathFor(const std::filesystem::path& path, const CliOptions& options, Integrator integrator) {
  if (options.integrators.size() <= 1) return path;
  std::filesystem::path named = path;
  named.replace_filename(path.stem().string() + "_" + std::string(integratorName(integrator)) +
                         path.extension().string());
  return named;
}

std::string_view integratorName(Integrator integrator) {
  switch (integrator) {
    case Integrator::Lightmap: return "lightmap";
    case Integrator::Direct: return "direct";
    case Integrator::Path: return "path";
  }
  return "?";
}

std::string_view tonemapName(Tonemap tonemap) {
  switch (tonemap) {
    case Tonemap::AcesFitted: return "aces";
    case Tonemap::Reinhard: return "reinhard";
    case Tonemap::Clamp: return "clamp";
  }
  return "?";
}

ParseResult parseCommandLine(std::span<const std::string_view> args) {
  ParseResult result;
  CliOptions& o = result.options;
  std::string& message = result.message;
  std::vector<std::string_view> positional;

  for (size_t i = 0; i < args.size(); ++i) {
    std::string_view arg = args[i];
    if (arg == "-h" || arg == "--help") {
      result.status = ParseStatus::Help;
      return result;
    }
    if (arg.size() < 2 || arg[0] != '-') {
      positional.push_back(arg);
      continue;
    }
    if (arg == "--") {
      positional.insert(positional.end(), args.begin() + static_cast<std::ptrdiff_t>(i) + 1, args.end());
      break;
    }
    // Split "--name=value".
    std::string_view name = arg;
    std::optional<std::string_view> inlineValue;
    if (const size_t eq = arg.find('='); eq != std::string_view::npos && arg.starts_with("--")) {
      name = arg.substr(0, eq);
      inlineValue = arg.substr(eq + 1);
    }
    if (name == "--progress" || name == "--quiet" || name == "-q" || name == "--denoise" ||
        name == "--no-camera-packets" || name == "--restir" || name == "--spread-fireflies" ||
        name == "--baked-path-end" || name == "--no-lamp-visibility" || name == "--no-temporal-gradients") {
      if (inlineValue) {
        message = std::string(name) + " takes no value";
        return result;
      }
      if (name == "--no-camera-packets") {
        o.cameraPackets = false;
      } else if (name == "--no-lamp-visibility") {
        o.lampVisibility = false;
      } else if (name == "--no-temporal-gradients") {
        o.temporalGradients = false;
      } else if (name == "--restir") {
        o.restir = true;
      } else if (name == "--baked-path-end") {
        o.bakedPathEnd = true;
      } else if (name == "--spread-fireflies") {
        o.spreadFireflies = true;
      } else {
        (name == "--progress" ? o.progress : name == "--denoise" ? o.denoise : o.quiet) = true;
      }
      continue;
    }
    std::string_view value;
    if (inlineValue) {
      value = *inlineValue;
    } else if (i + 1 < args.size()) {
      value = args[++i];
    } else {
      message = std::string(name) + ": missing value";
      return result;
    }
    bool ok = true;
    if (name == "-o" || name == "--output") {
      o.pngOut = std::filesystem::path(value);
      ok = !value.empty();
      if (!ok) message = "-o: empty file name";
    } else if (name == "--exr") {
      o.exrOut = std::filesystem::path(value);
      ok = !value.empty();
      if (!ok) message = "--exr: empty file name";
    } else if (name == "--stats") {
      o.statsOut = std::filesystem::path(value);
      ok = !value.empty();
      if (!ok) message = "--stats: empty file name";
    } else if (name == "--width") {
      ok = parseUnsigned(name, value, 1, kMaxImageSide, o.width, message);
    } else if (name == "--height") {
      ok = parseUnsigned(name, value, 1, kMaxImageSide, o.height, message);
    } else if (name == "--spp") {
      ok = parseUnsigned(name, value, 1, 1u << 20, o.samplesPerPixel, message);
    } else if (name == "--frames") {
      ok = parseUnsigned(name, value, 1, 1u << 20, o.frames, message);
    } else if (name == "--bounces") {
      ok = parseUnsigned(name, value, 0, 1024, o.bounces, message);
    } else if (name == "--roulette-start") {
      ok = parseUnsigned(name, value, 1, 1024, o.rouletteStart, message);
    } else if (name == "--seed") {
      ok = parseUnsigned(name, value, 0, std::numeric_limits<uint32_t>::max(), o.seed, message);
    } else if (name == "--threads") {
      ok = parseUnsigned(name, value, 0, 4096, o.threads, message);
    } else if (name == "--camera") {
      ok = parseUnsigned(name, value, 0, 1u << 20, o.camera, message);
    } else if (name == "--clamp") {
      ok = parseFloat(name, value, 0.0f, false, o.clamp, message);
    } else if (name == "--exposure") {
      o.autoExposure = value == "auto";
      if (!o.autoExposure) ok = parseFloat(name, value, 0.0f, true, o.exposure, message);
      if (!ok) message += " or \"auto\"";
    } else if (name == "--light-scale") {
      ok = parseFloat(name, value, 0.0f, true, o.lightScale, message);
    } else if (name == "--integrator") {
      ok = parseIntegrators(value, o.integrators, message);
    } else if (name == "--play") {
      if (value == "accumulate") o.play = CliOptions::Play::Accumulate;
      else if (value == "independent") o.play = CliOptions::Play::Independent;
      else if (value == "temporal") o.play = CliOptions::Play::Temporal;
      else {
        ok = false;
        message = "--play: expected accumulate, independent or temporal, got \"" + std::string(value) + "\"";
      }
    } else if (name == "--lighting") {
      if (value == "physical") o.lighting = LightingLook::Physical;
      else if (value == "display") o.lighting = LightingLook::DisplaySpace;
      else {
        ok = false;
        message = "--lighting: expected physical or display, got \"" + std::string(value) + "\"";
      }
    } else if (name == "--tonemap") {
      if (value == "aces") o.tonemap = Tonemap::AcesFitted;
      else if (value == "reinhard") o.tonemap = Tonemap::Reinhard;
      else if (value == "clamp") o.tonemap = Tonemap::Clamp;
      else {
        ok = false;
        message = "--tonemap: expected aces, reinhard or clamp, got \"" + std::string(value) + "\"";
      }
    } else {
      message = "unknown option " + std::string(name) + " (see --help)";
      return result;
    }
    if (!ok) return result;
  }
  if (positional.size() != 1) {
    message = positional.empty() ? "missing input scene (see --help)"
                                 : "expected one input scene, got " + std::to_string(positional.size());
    return result;
  }
  o.scene = std::filesystem::path(positional[0]);
  if (o.pngOut.empty()) {
    message = "missing -o OUTPUT.png";
    return result;
  }
  if (o.progress && o.quiet) {
    message = "--progress and --quiet contradict each other";
    return result;
  }
  result.status = ParseStatus::Ok;
  return result;
}

std::string usageText(std::string_view program) {
  std::string text = "Usage: " + std::string(program) + " SCENE -o OUT.png [options]\n";
  text += R"(
Renders a scene with the PathArena CPU path tracer and writes a tonemapped PNG
(and optionally a linear OpenEXR with AOV layers).

Input (the importer is chosen by the file extension):
  SCENE                  .gltf or .glb (glTF 2.0: meshes, node transforms, metallic-roughness
                         materials, alpha MASK/BLEND, emissive (+KHR_materials_emissive_strength),
                         KHR_texture_transform, KHR_lights_punctual, perspective cameras;
                         scene extras "sky_color": [r,g,b] and "sky_intensity" set the sky)

Output:
  -o, --output FILE      PNG: exposure, tonemap and sRGB applied by the renderer (required;
                         missing folders are created)
  --exr FILE             OpenEXR, 32-bit float: R,G,B = linear mean radiance (no exposure),
                         albedo.{R,G,B}, normal.{X,Y,Z} (world space), Z = first-hit distance
                         (inf = sky), variance.Y = variance of the mean's luminance
  --stats FILE           JSON summary for scripts: scene, camera (index, name), triangles,
                         lights, image size, integrator, tonemap, exposure (the gain applied),
                         auto_exposure (with --exposure auto: gain, key, target, range,
                         clamped), spp, frames, load and render seconds
                         (first_frame_seconds: the first frame alone, which also builds
                         what later frames reuse), sky_fraction (pixels whose first hit is
                         sky or nothing)

Image and sampling:
  --width W, --height H  Image size in pixels (1..16384). Default width 640; a missing side
                         follows the camera's aspect ratio (16:9 if the camera has none)
  --spp N                Samples per pixel per frame (default 16)
  --frames F             Frames accumulated into one image (default 1): total = F x N spp.
                         The progress bar advances per frame.
  --integrator NAME      lightmap | direct | path (default path)
                           lightmap: primary rays x baked light (the stock look)
                           direct:   direct light with ray-traced shadows + emission
                           path:     full path tracing (NEE + MIS, Russian roulette)
                         A list NAME[:SPP],... renders each over the scene loaded once, in
                         that order, SPP samples per pixel per frame (default --spp); each
                         output file gets "_NAME" before its extension (-o out.png:
                         out_lightmap.png, out_direct.png), and the pictures are the same
                         as those of one run per integrator. With --exposure auto, the first
                         picture is metered and its gain exposes them all
  --bounces N            Maximum path length for 'path' (default 4)
  --baked-path-end       direct and path: a path's last vertex on a surface with baked light
                         (lightmap or vertex light, as .bsp maps have) reflects the bake's
                         light there instead of ending dark (the compiler's bounced light)
  --roulette-start N     direct and path: scatterings after which Russian roulette may end a
                         path (default 3; 1: the first bounce ray is traced with the probability
                         of the surface's albedo, its light divided by it: unbiased, faster, noisier)
  --clamp X              Clamp each path's contribution to X (0 = off, unbiased; default 0)
  --seed S               Random seed (default 0); the image depends only on scene, camera,
                         seed, frames and spp, never on the thread count
  --threads T            Worker threads (default 0 = all cores)
  --denoise              Edge-aware a-trous filter of the image (albedo/normal/depth guided;
                         meant for 1..few spp): the PNG and the EXR's R,G,B are filtered
  --spread-fireflies     With --denoise or --play temporal: before the denoiser, cut pixels far
                         brighter than their neighbourhood and share the excess among their
                         neighbours on the same surface (keeps the image's energy)
  --no-camera-packets    Trace camera rays one by one instead of in 4x4 packets (same image;
                         for speed comparisons)
  --no-lamp-visibility   Weigh each lamp by its unshadowed contribution alone, not less where
                         no shadow ray from the surfaces around reached it (RendererConfig::
                         lampVisibility; for comparisons)
  --restir               Direct light at each pixel's first hit by spatiotemporal reservoir
                         resampling (ReSTIR DI, renderer/scene/restir) instead of one light
                         sample; direct and path only. --stats gets resample_seconds and
                         trace_seconds (summed over the frames)
  --play MODE            How the F frames combine: accumulate (default: one mean of F x N spp);
                         independent (as the game's direct/path: seed + frame, no accumulation,
                         the last frame is written); temporal (the same with temporal
                         accumulation, renderer/scene/temporal). With independent or temporal,
                         --stats gets frame_change: mean absolute change of display luma (0..1)
                         between consecutive frames over the last 8 pairs
  --no-temporal-gradients
                         With --play temporal: no temporal gradients (RenderSettings::
                         temporalGradients; for comparisons)

View:
  --camera INDEX         Camera of the scene to render (default 0). Without any camera in the
                         file, a camera framing the whole scene is made up.
  --exposure E|auto      Linear multiplier before tonemapping (default 1). auto: metered on
                         the rendered image: the log-average luminance of the pixels that see
                         the world (not the sky; all pixels if none does), black clipped at
                         0.001, is brought to 0.045 (a low-key scene); the gain is clamped to
                         [1/8, 16] and reported in --stats (auto_exposure) and the summary.
                         The EXR stays unexposed
  --tonemap NAME         PNG display transform: aces (filmic, default) | reinhard (luminance,
                         hue kept) | clamp (no curve: the stock renderer's look, best with
                         --integrator lightmap)
  --lighting NAME        PNG look of reflected light: physical (default) | display (texture x
                         light multiplied in 8-bit display values, light clamped to 1, as a
                         light-mapped engine shows it; best with --tonemap clamp)
  --light-scale X        glTF photometric units -> renderer units: multiplies light intensities
                         (candela, lux) and emissive strengths alike (default 1)

Reporting:
  --progress             Progress bar with ETA on stderr even when stderr is not a terminal
                         (it is shown by default on a terminal)
  -q, --quiet            No progress bar, no importer warnings
  -h, --help             This text

A one-line summary (size, samples, time, output) is always printed on stderr.

Exit status: 0 success, 1 load/render/write failure (message on stderr), 2 usage error.

Example:
  pa-render renderer/cli/scenes/default_arena.gltf -o out/default.png --spp 64 --exr out/default.exr
)";
  return text;
}

}  // namespace pa::cli
