// Running pa-render as a child process (fork/exec, no shell) and reading PNG/EXR/JSON back.
#include "tests/all_maps_render/render_run.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <stb_image.h>
#include <tinyexr.h>

namespace pa::allmaps {
namespace {

/// Runs argv[0] with stdout and stderr sent to `logPath`; returns the exit status (-1 if it
/// could not start or did not exit normally).
int runAndWait(const std::vector<std::string>& argv, const std::filesystem::path& logPath) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t child = ::fork();
  if (child < 0) return -1;
  if (child == 0) {
    const int log = ::open(logPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (log >= 0) {
      ::dup2(log, STDOUT_FILENO);
      ::dup2(log, STDERR_FILENO);
      ::close(log);
    }
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(child, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// The outputs of one integrator of a request (pa-render's naming: "_NAME" with more than one).
struct IntegratorFiles {
  std::filesystem::path png, exr, json;
};

/// STEM followed by `suffix` ("_direct.png", ".log").
std::filesystem::path stemWith(const std::filesystem::path& stem, const std::string& suffix) {
  std::filesystem::path p = stem;
  p += suffix;
  return p;
}

IntegratorFiles filesFor(const RenderRequest& r, const IntegratorRequest& integrator) {
  const std::string name = r.integrators.size() > 1 ? "_" + integrator.name : "";
  return {stemWith(r.outputStem, name + ".png"), stemWith(r.outputStem, name + ".exr"),
          stemWith(r.outputStem, name + ".json")};
}

/// pa-render's command line for a request.
std::vector<std::string> renderCommand(const RenderRequest& r) {
  std::string integrators;
  for (const IntegratorRequest& i : r.integrators)
    integrators += (integrators.empty() ? "" : ",") + i.name + ":" + std::to_string(i.samplesPerPixel);
  // pa-render names each integrator's files itself (STEM_NAME.* with more than one: filesFor).
  std::vector<std::string> command = {r.paRender.string(), r.scene.string(), "-o", stemWith(r.outputStem, ".png").string(),
          "--exr", stemWith(r.outputStem, ".exr").string(), "--stats", stemWith(r.outputStem, ".json").string(),
          "--integrator", integrators, "--tonemap", r.tonemap, "--camera", std::to_string(r.camera), "--width", std::to_string(r.width),
          "--height", std::to_string(r.height), "--threads",
          std::to_string(r.threads), "--seed", "0", "--exposure", r.exposure, "--quiet"};
  command.insert(command.end(), r.extraArguments.begin(), r.extraArguments.end());
  return command;
}

std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// True when a --stats record was made with --exposure `exposure` ("auto" or a gain).
bool sameExposure(const nlohmann::json& stats, const std::string& exposure) {
  // (a later integrator of an "auto" run records the first one's metering: auto_exposure is set)
  const bool metered = stats.contains("auto_exposure") && stats["auto_exposure"].is_object();
  if (exposure == "auto") return metered;
  if (metered || !stats.contains("exposure") || !stats["exposure"].is_number()) return false;
  return std::abs(stats["exposure"].get<double>() - std::strtod(exposure.c_str(), nullptr)) <= 1e-6 * std::abs(stats["exposure"].get<double>());
}

/// Linear radiance -> display RGBA8 at exposure 1 with the clamp tonemap (IEC 61966-2-1 sRGB).
RgbaImage encodeUnexposed(uint32_t width, uint32_t height, const std::vector<float>& r, const std::vector<float>& g,
                          const std::vector<float>& b) {
  auto encode = [](float linear) {
    const double x = std::clamp(std::isfinite(linear) ? double{linear} : 0.0, 0.0, 1.0);
    const double srgb = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return static_cast<uint8_t>(std::lround(srgb * 255.0));
  };
  RgbaImage image{width, height, std::vector<uint8_t>(size_t{width} * height * 4, 255)};
  for (size_t i = 0; i < size_t{width} * height; ++i) {
    image.pixels[i * 4 + 0] = encode(r[i]);
    image.pixels[i * 4 + 1] = encode(g[i]);
    image.pixels[i * 4 + 2] = encode(b[i]);
  }
  return image;
}

/// True when the --stats file at `json` was written by a render of `integrator` with the settings of `r`.
bool madeWithSettings(const std::filesystem::path& json, const RenderRequest& r, const IntegratorRequest& integrator) {
  if (!std::filesystem::exists(json)) return false;
  const nlohmann::json stats = nlohmann::json::parse(readText(json), nullptr, false);
  if (!stats.is_object()) return false;
  return stats.value("scene", "") == r.scene.string() && stats.value("integrator", "") == integrator.name &&
         stats.value("tonemap", "") == r.tonemap && stats.value("camera_index", -1) == int64_t{r.camera} &&
         stats.value("width", 0u) == r.width && stats.value("height", 0u) == r.height &&
         stats.value("spp", 0u) == integrator.samplesPerPixel && sameExposure(stats, r.exposure);
}

RgbaImage readPng(const std::filesystem::path& path) {
  int width = 0, height = 0, channels = 0;
  stbi_uc* pixels = stbi_load(path.c_str(), &width, &height, &channels, 4);
  if (!pixels) throw std::runtime_error(path.string() + ": cannot read PNG");
  RgbaImage image{static_cast<uint32_t>(width), static_cast<uint32_t>(height),
                  std::vector<uint8_t>(pixels, pixels + size_t(width) * size_t(height) * 4)};
  stbi_image_free(pixels);
  return image;
}

}  // namespace

std::vector<float> readExrChannel(const std::filesystem::path& path, const std::string& name, uint32_t& width,
                                  uint32_t& height) {
  const std::string file = path.string();
  EXRVersion version;
  if (ParseEXRVersionFromFile(&version, file.c_str()) != TINYEXR_SUCCESS)
    throw std::runtime_error(file + ": not an OpenEXR file");
  if (version.multipart || version.tiled) throw std::runtime_error(file + ": expected a single-part scanline EXR");
  EXRHeader header;
  InitEXRHeader(&header);
  const char* error = nullptr;
  auto fail = [&](const std::string& what) -> std::runtime_error {
    std::string message = file + ": " + what;
    if (error) {
      message += std::string(": ") + error;
      FreeEXRErrorMessage(error);
    }
    return std::runtime_error(message);
  };
  if (ParseEXRHeaderFromFile(&header, &version, file.c_str(), &error) != TINYEXR_SUCCESS) throw fail("bad header");
  for (int c = 0; c < header.num_channels; ++c) header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
  EXRImage image;
  InitEXRImage(&image);
  if (LoadEXRImageFromFile(&image, &header, file.c_str(), &error) != TINYEXR_SUCCESS) {
    FreeEXRHeader(&header);
    throw fail("cannot decode");
  }
  std::vector<float> values;
  bool found = false;
  for (int c = 0; c < header.num_channels && !found; ++c) {
    if (name != header.channels[c].name) continue;
    const float* plane = reinterpret_cast<const float*>(image.images[c]);
    values.assign(plane, plane + size_t(image.width) * size_t(image.height));
    found = true;
  }
  width = static_cast<uint32_t>(image.width);
  height = static_cast<uint32_t>(image.height);
  FreeEXRImage(&image);
  FreeEXRHeader(&header);
  if (!found) throw std::runtime_error(file + ": no channel \"" + name + "\"");
  return values;
}

namespace {

/// Reads one integrator's outputs back into `result` (error set when something is missing).
void readOutputs(const IntegratorFiles& files, bool firstIntegrator, RenderResult& result) {
  try {
    const nlohmann::json stats = nlohmann::json::parse(readText(files.json));
    result.cameraName = stats.at("camera").get<std::string>();
    result.triangles = stats.at("triangles").get<uint64_t>();
    result.lights = stats.at("lights").get<uint64_t>();
    result.renderMilliseconds = 1000.0 * stats.at("render_seconds").get<double>();
    result.wallMilliseconds =
        result.renderMilliseconds + (firstIntegrator ? 1000.0 * stats.at("load_seconds").get<double>() : 0.0);
    result.exposure = stats.at("exposure").get<double>();
    if (stats.contains("auto_exposure") && stats["auto_exposure"].is_object())
      result.exposureAtMaxGain = stats["auto_exposure"].value("clamped", "") == "max";
    result.image = readPng(files.png);
    uint32_t width = 0, height = 0;
    result.depth = readExrChannel(files.exr, "Z", width, height);
    if (width != result.image.width || height != result.image.height)
      throw std::runtime_error(files.exr.string() + ": size differs from the PNG's");
    const std::vector<float> red = readExrChannel(files.exr, "R", width, height),
                             green = readExrChannel(files.exr, "G", width, height),
                             blue = readExrChannel(files.exr, "B", width, height);
    result.unexposedImage = encodeUnexposed(width, height, red, green, blue);
  } catch (const std::exception& e) {
    result.error = e.what();
  }
}

}  // namespace

std::vector<RenderResult> runPaRender(const RenderRequest& r) {
  std::vector<RenderResult> results(r.integrators.size());
  std::filesystem::create_directories(r.outputStem.parent_path());
  const std::filesystem::path log = stemWith(r.outputStem, ".log");
  std::vector<IntegratorFiles> files;
  for (const IntegratorRequest& integrator : r.integrators) files.push_back(filesFor(r, integrator));
  bool reuse = r.reuseExisting && !r.integrators.empty();
  for (size_t k = 0; k < r.integrators.size(); ++k)
    reuse = reuse && std::filesystem::exists(files[k].png) && std::filesystem::exists(files[k].exr) &&
            madeWithSettings(files[k].json, r, r.integrators[k]);
  int exitCode = 0;
  if (!reuse) {
    for (const IntegratorFiles& f : files)
      for (const auto& p : {f.png, f.exr, f.json}) std::filesystem::remove(p);
    exitCode = runAndWait(renderCommand(r), log);
  }
  const std::string logText = readText(log);
  for (size_t k = 0; k < r.integrators.size(); ++k) {
    RenderResult& result = results[k];
    result.exitCode = exitCode;
    result.log = logText;
    // pa-render writes an integrator's --stats last: without it, that integrator did not finish.
    if (exitCode != 0 && !std::filesystem::exists(files[k].json)) {
      result.error = "pa-render exited with " + std::to_string(exitCode);
      continue;
    }
    readOutputs(files[k], k == 0, result);
  }
  return results;
}

}  // namespace pa::allmaps
