#include "port/engine_glue/settings.h"

#include <algorithm>
#include <cmath>

#include "port/engine_glue/engine.h"

namespace glue {

Preset parsePreset(const std::string& name, bool& known) {
  const std::string n = normalizeName(name);
  known = true;
  if (n == "lightmap") return Preset::Lightmap;
  if (n == "direct") return Preset::Direct;
  if (n == "path") return Preset::Path;
  if (n == "reference") return Preset::Reference;
  known = false;
  return Preset::Path;
}

const char* presetName(Preset preset) {
  switch (preset) {
    case Preset::Lightmap: return "lightmap";
    case Preset::Direct: return "direct";
    case Preset::Path: return "path";
    case Preset::Reference: return "reference";
  }
  return "path";
}

void Settings::registerCvars(const Engine& engine) {
  using namespace q3abi;
  const auto& ri = engine.ri();
  mode_ = engine.cvar("r_mode", "-2", CVAR_ARCHIVE | CVAR_LATCH,
                      "Video mode: -2 desktop size, -1 r_customwidth x r_customheight, "
                      "0..28 the stock mode table");
  if (mode_ != nullptr) ri.Cvar_CheckRange(mode_, -2, 28, 1);
  customWidth_ = engine.cvar("r_customwidth", "1600", CVAR_ARCHIVE | CVAR_LATCH,
                             "Window width when r_mode is -1");
  customHeight_ = engine.cvar("r_customheight", "1024", CVAR_ARCHIVE | CVAR_LATCH,
                              "Window height when r_mode is -1");
  fullscreen_ = engine.cvar("r_fullscreen", "1", CVAR_ARCHIVE | CVAR_LATCH, "Fullscreen window");
  preset_ = engine.cvar("r_pt_preset", "lightmap", CVAR_ARCHIVE,
                        "Path tracer quality: lightmap | direct | path | reference");
  spp_ = engine.cvar("r_pt_spp", "1", CVAR_ARCHIVE, "Samples per pixel per frame (1..256)");
  if (spp_ != nullptr) ri.Cvar_CheckRange(spp_, 1, 256, 1);
  bounces_ = engine.cvar("r_pt_bounces", "2", CVAR_ARCHIVE, "Maximum path bounces (0..16)");
  if (bounces_ != nullptr) ri.Cvar_CheckRange(bounces_, 0, 16, 1);
  scale_ = engine.cvar("r_pt_scale", "0.5", CVAR_ARCHIVE,
                       "Internal resolution as a fraction of the window (0.1..1)");
  if (scale_ != nullptr) ri.Cvar_CheckRange(scale_, 0.1f, 1.0f, 0);
  threads_ = engine.cvar("r_pt_threads", "0", CVAR_ARCHIVE | CVAR_LATCH,
                         "Render threads (0 = all cores); applies after vid_restart");
  if (threads_ != nullptr) ri.Cvar_CheckRange(threads_, 0, 256, 1);
  seed_ = engine.cvar("r_pt_seed", "0", 0, "Random seed of the sampler");
  stats_ = engine.cvar("r_pt_stats", "0", 0,
                       "Print traced views per second and milliseconds per traced frame");
  denoise_ = engine.cvar("r_pt_denoise", "1", CVAR_ARCHIVE,
                         "Edge-aware denoiser on the direct and path presets (0 = raw samples)");
  if (denoise_ != nullptr) ri.Cvar_CheckRange(denoise_, 0, 1, 1);
  temporal_ = engine.cvar("r_pt_temporal", "1", CVAR_ARCHIVE,
                          "Temporal accumulation (reprojected history) on the direct and path presets (0 = off)");
  if (temporal_ != nullptr) ri.Cvar_CheckRange(temporal_, 0, 1, 1);
}

VideoModeRequest Settings::videoMode() const {
  VideoModeRequest request;
  if (mode_ != nullptr) request.mode = mode_->integer;
  if (customWidth_ != nullptr) request.customWidth = customWidth_->integer;
  if (customHeight_ != nullptr) request.customHeight = customHeight_->integer;
  if (fullscreen_ != nullptr) request.fullscreen = fullscreen_->integer != 0;
  return request;
}

TracerSettings Settings::tracer(const Engine& engine) const {
  TracerSettings out;
  if (preset_ != nullptr && preset_->string != nullptr) {
    bool known = true;
    out.preset = parsePreset(preset_->string, known);
    if (!known && preset_->modified) {
      engine.warn(std::string("r_pt_preset '") + preset_->string +
                  "' unknown: use lightmap, direct, path or reference");
    }
    preset_->modified = 0;
  }
  if (spp_ != nullptr) out.samplesPerPixel = std::clamp(spp_->integer, 1, 256);
  if (bounces_ != nullptr) out.maxBounces = std::clamp(bounces_->integer, 0, 16);
  if (scale_ != nullptr && std::isfinite(scale_->value))
    out.resolutionScale = std::clamp(scale_->value, 0.1f, 1.0f);
  if (threads_ != nullptr) out.threads = std::clamp(threads_->integer, 0, 256);
  if (seed_ != nullptr) out.seed = static_cast<uint32_t>(seed_->integer);
  out.printStats = stats_ != nullptr && stats_->integer != 0;
  out.denoise = denoise_ == nullptr || denoise_->integer != 0;
  out.temporal = temporal_ == nullptr || temporal_->integer != 0;
  return out;
}

}  // namespace glue
