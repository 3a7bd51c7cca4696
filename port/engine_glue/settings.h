#pragma once
// The module's cvars: the stock video-mode ones and the path tracer's r_pt_* knobs.
#include <cstdint>
#include <string>

#include "port/engine_glue/ioq3_abi.h"
#include "port/engine_glue/window.h"

namespace glue {

class Engine;

/// Quality presets, cheapest first (r_pt_preset).
enum class Preset : uint8_t { Lightmap, Direct, Path, Reference };

/// Parses a preset name ("lightmap", "direct", "path", "reference"); Path when unknown.
Preset parsePreset(const std::string& name, bool& known);
/// The preset's cvar spelling.
const char* presetName(Preset preset);

/// Current path tracer settings, read from the cvars each frame.
struct TracerSettings {
  Preset preset = Preset::Path;
  int samplesPerPixel = 1;
  int maxBounces = 2;
  float resolutionScale = 0.5f;
  int threads = 0;
  uint32_t seed = 0;
  bool printStats = false;   ///< r_pt_stats
  bool denoise = true;       ///< r_pt_denoise: filter the direct and path presets' frames
  bool temporal = true;      ///< r_pt_temporal: temporal accumulation on the direct and path presets
};

/// Pointers to the engine's cvars (owned by the engine, valid while the module is loaded).
class Settings {
 public:
  /// Registers every cvar with its default, range and description.
  void registerCvars(const Engine& engine);
  /// The video mode the cvars ask for.
  VideoModeRequest videoMode() const;
  /// The tracer knobs, clamped to their documented ranges.
  TracerSettings tracer(const Engine& engine) const;

 private:
  q3abi::cvar_t* mode_ = nullptr;
  q3abi::cvar_t* customWidth_ = nullptr;
  q3abi::cvar_t* customHeight_ = nullptr;
  q3abi::cvar_t* fullscreen_ = nullptr;
  q3abi::cvar_t* preset_ = nullptr;
  q3abi::cvar_t* spp_ = nullptr;
  q3abi::cvar_t* bounces_ = nullptr;
  q3abi::cvar_t* scale_ = nullptr;
  q3abi::cvar_t* threads_ = nullptr;
  q3abi::cvar_t* seed_ = nullptr;
  q3abi::cvar_t* stats_ = nullptr;
  q3abi::cvar_t* denoise_ = nullptr;
  q3abi::cvar_t* temporal_ = nullptr;
};

}  // namespace glue
