#pragma once
// The module's cvars: the stock video-mode and picture ones and the path tracer's r_pt_* knobs.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "port/engine_glue/flares.h"
#include "port/engine_glue/ioq3_abi.h"
#include "port/engine_glue/window.h"
#include "renderer/scene/scene_types.h"

namespace glue {

class Engine;

/// Quality presets, cheapest first (r_pt_preset).
enum class Preset : uint8_t { Lightmap, Direct, Path, Reference };

/// Parses a preset name ("lightmap", "direct", "path", "reference"); Path when unknown.
Preset parsePreset(const std::string& name, bool& known);
/// The preset's cvar spelling.
const char* presetName(Preset preset);
/// True for direct and path: the presets that trace light in real time, a few samples a frame
/// filtered over frames (lightmap shows the bake; reference accumulates one view).
bool isRealTimeTraced(Preset preset);
/// The traced world view's scale in effect: r_pt_scale's value in [0.1, 1], or while it is 0 (its
/// default) or not a number the preset's own: 0.35 for direct and path, which TAAU brings to the
/// window (effectiveTaau), 0.5 for the others (docs/performance.md "`direct` and `path` at 0.35 of
/// the window through TAAU").
float effectiveScale(float cvarValue, Preset preset);
/// r_pt_taau's mode in effect (0..2): the cvar's, or while it is negative (-1, its default) the
/// preset's own: 1 for direct and path, 0 for lightmap (whose frame costs less to trace than TAAU
/// costs to resolve) and reference.
int effectiveTaau(int cvarValue, Preset preset);
/// r_pt_taau_size in effect: the cvar's value in [0.25, 1]; 1 (the window) when it is not a number.
float effectiveTaauSize(float cvarValue);
/// The size TAAU resolves a world view of viewWidth x viewHeight, traced at tracedWidth x
/// tracedHeight, to: the view's size times taauSize (rounded), never below the traced size.
std::array<uint32_t, 2> taauOutputSize(uint32_t viewWidth, uint32_t viewHeight, uint32_t tracedWidth,
                                       uint32_t tracedHeight, float taauSize);

/// Parses a stock r_textureMode value (GL_NEAREST, GL_LINEAR, GL_{NEAREST,LINEAR}_MIPMAP_{NEAREST,
/// LINEAR}, any case) into the filter it names; the stock default GL_LINEAR_MIPMAP_NEAREST when unknown.
pa::TextureFilter parseTextureMode(const std::string& name, bool& known);

/// Current path tracer settings, read from the cvars each frame.
struct TracerSettings {
  Preset preset = Preset::Path;
  int samplesPerPixel = 1;
  int maxBounces = 2;
  float resolutionScale = 0.5f;   ///< r_pt_scale in effect (effectiveScale)
  int threads = 0;
  uint32_t seed = 0;
  bool printStats = false;   ///< r_pt_stats
  bool denoise = true;       ///< r_pt_denoise: filter the direct and path presets' frames
  bool temporal = true;      ///< r_pt_temporal: temporal accumulation on the direct and path presets
  bool restir = false;       ///< r_pt_restir: reservoir resampling of direct light on the direct and path presets
  uint32_t gradientStratum = 6;   ///< r_pt_gradients: temporal gradients' block side (0 = off; with temporal)
  bool bakedEnd = true;      ///< r_pt_bake_end: paths end on the bake's light (RenderSettings::bakedLightAtPathEnd)
  int rouletteStart = 1;     ///< r_pt_roulette: scatterings before Russian roulette (RenderSettings::rouletteStart)
  /// r_pt_taau: temporal anti-aliasing and upscaling to the window of world views; 0 = off (bilinear
  /// stretch), 1 = when traced smaller than the window, 2 = always (also anti-aliases r_pt_scale 1);
  /// in effect (effectiveTaau)
  int taau = 0;
  /// r_pt_taau_size in effect (effectiveTaauSize): TAAU's output as a fraction of the window
  /// (taauOutputSize), which the presentation stretches to the window (on the CPU where it is half).
  float taauSize = 1.0f;
  float targetFps = 0.0f;    ///< r_pt_fps: dynamic resolution's frame-rate target (0 = off: r_pt_scale as set)
  float minScale = 0.35f;    ///< r_pt_scale_min: the least scale dynamic resolution may pick
  /// r_pt_look: the traced presets show light as the lightmap does (texture x light in display
  /// values, light clamped to 1, no tone curve); false: physical radiance through the ACES curve
  bool stockLook = true;
  bool fireflies = true;     ///< r_pt_fireflies: spread fireflies before the denoiser (denoise/fireflies.h)
  bool captureExr = false;   ///< r_pt_captureExr: screenshots also write the world view's film as EXR
  /// r_pt_pipeline: the world view is traced while the game goes on and shown one frame later
  /// (the HUD of that frame over it); false: each frame shows its own world view
  bool pipeline = true;
  float radianceClamp = -1.0f;   ///< r_pt_clamp: per-sample radiance clamp (0 = none); < 0 = the preset's
  /// r_pt_isa avx2: the BVHs keep the AVX2 kernels and 8-wide layout on a CPU with AVX-512 (to
  /// measure what CPUs without it run); auto: the fastest this CPU has. Latched (vid_restart).
  bool avx2Kernels = false;
  /// r_pt_lamp_vis: lamps no shadow ray from a region's surfaces reached are chosen less often
  /// there (RendererConfig::lampVisibility); false weighs every lamp unshadowed. Latched.
  bool lampVisibility = true;
  /// r_textureMode: how the lightmap look filters world and model textures, as stock's texture units
  pa::TextureFilter textureFilter{pa::MipFilter::Nearest, false};
};

/// The stock picture cvars with their stock defaults (tr_init.c): display gamma, texture detail,
/// overbright bits, texture intensity, flares.
struct PictureSettings {
  float gamma = 1.0f;          ///< r_gamma in [0.5, 3] (stock sets it back into that range).
  int picmip = 0;              ///< r_picmip in [0, 16]: mipmapped textures are halved this many times.
  int overBrightBits = 1;      ///< r_overBrightBits as set (see displayOverBrightBits).
  int mapOverBrightBits = 2;   ///< r_mapOverBrightBits: baked light is brightened by 2^(this - display bits).
  float intensity = 1.0f;      ///< r_intensity, at least 1: mipmapped texture bytes are multiplied by it.
  bool fullscreen = false;     ///< The window is fullscreen (glconfig isFullscreen; set by the module).
  bool flares = false;         ///< r_flares: the map's light flares over views of the world (flares.h).
  FlareParams flare;           ///< r_flareSize, r_flareFade, r_flareCoeff.

  /// Overbright bits of the display, as stock opengl1 decides them (R_SetColorMappings): in a
  /// window 0; fullscreen r_overBrightBits in [0, 2] (24-bit colour, gamma ramp available).
  int displayOverBrightBits() const;
  /// 2^displayOverBrightBits: stock draws lit surfaces at half and its gamma ramp doubles the
  /// frame; the module multiplies texture x baked light by this in display values instead.
  float bakedLightScale() const { return static_cast<float>(1 << displayOverBrightBits()); }
  /// The shift that brightens lightmaps and baked vertex light: r_mapOverBrightBits minus the
  /// display's overbright bits, at least 0.
  int lightShift() const;
};

/// The stock gamma ramp: entry i is 255 (i / 255)^(1 / gamma) + 0.5 truncated (i when gamma is
/// 1), shifted left by `overbrightBits`, at most 255.
std::array<uint8_t, 256> gammaRamp(float gamma, int overbrightBits);

/// True when a ramp maps every byte to itself.
bool isIdentityRamp(const std::array<uint8_t, 256>& ramp);

/// The stock texture intensity table applied to a mipmapped texture's colour bytes: byte x
/// intensity truncated, at most 255 (alpha kept). RGBA8 in place.
void applyIntensity(std::vector<uint8_t>& rgba, float intensity);

/// An RGBA8 image halved `times` times (2x2 box averages, odd sizes dropping the last row or
/// column, never below 1 x 1), as r_picmip shrinks mipmapped textures.
std::vector<uint8_t> picmipImage(const std::vector<uint8_t>& rgba, int& width, int& height, int times);

/// Pointers to the engine's cvars (owned by the engine, valid while the module is loaded).
class Settings {
 public:
  /// Registers every cvar with its default, range and description.
  void registerCvars(const Engine& engine);
  /// The video mode the cvars ask for.
  VideoModeRequest videoMode() const;
  /// The tracer knobs, clamped to their documented ranges.
  TracerSettings tracer(const Engine& engine) const;
  /// The stock picture cvars; r_gamma and r_intensity are set back into their stock ranges.
  PictureSettings picture(const Engine& engine) const;
  /// True (once) when r_gamma changed since the last call.
  bool gammaChanged() const;
  /// r_dynamiclight: false when the game's dynamic lights are to be left out, as stock does at 0.
  bool dynamicLights() const;

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
  q3abi::cvar_t* gamma_ = nullptr;
  q3abi::cvar_t* picmip_ = nullptr;
  q3abi::cvar_t* dynamicLight_ = nullptr;
  q3abi::cvar_t* overBrightBits_ = nullptr;
  q3abi::cvar_t* mapOverBrightBits_ = nullptr;
  q3abi::cvar_t* intensity_ = nullptr;
  q3abi::cvar_t* flares_ = nullptr;
  q3abi::cvar_t* flareSize_ = nullptr;
  q3abi::cvar_t* flareFade_ = nullptr;
  q3abi::cvar_t* flareCoeff_ = nullptr;
  q3abi::cvar_t* temporal_ = nullptr;
  q3abi::cvar_t* taau_ = nullptr;
  q3abi::cvar_t* taauSize_ = nullptr;
  q3abi::cvar_t* fps_ = nullptr;
  q3abi::cvar_t* scaleMin_ = nullptr;
  q3abi::cvar_t* restir_ = nullptr;
  q3abi::cvar_t* gradients_ = nullptr;
  q3abi::cvar_t* bakedEnd_ = nullptr;
  q3abi::cvar_t* roulette_ = nullptr;
  q3abi::cvar_t* look_ = nullptr;
  q3abi::cvar_t* fireflies_ = nullptr;
  q3abi::cvar_t* captureExr_ = nullptr;
  q3abi::cvar_t* pipeline_ = nullptr;
  q3abi::cvar_t* clamp_ = nullptr;
  q3abi::cvar_t* isa_ = nullptr;
  q3abi::cvar_t* lampVisibility_ = nullptr;
  q3abi::cvar_t* textureMode_ = nullptr;
  mutable pa::TextureFilter textureFilter_{pa::MipFilter::Nearest, false};   ///< r_textureMode as last parsed
  mutable bool textureFilterRead_ = false;
};

}  // namespace glue
