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

pa::TextureFilter parseTextureMode(const std::string& name, bool& known) {
  const std::string n = normalizeName(name);
  known = true;
  if (n == "gl_nearest") return {pa::MipFilter::None, true};
  if (n == "gl_linear") return {pa::MipFilter::None, false};
  if (n == "gl_nearest_mipmap_nearest") return {pa::MipFilter::Nearest, true};
  if (n == "gl_linear_mipmap_nearest") return {pa::MipFilter::Nearest, false};
  if (n == "gl_nearest_mipmap_linear") return {pa::MipFilter::Linear, true};
  if (n == "gl_linear_mipmap_linear") return {pa::MipFilter::Linear, false};
  known = false;
  return {pa::MipFilter::Nearest, false};
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

bool isRealTimeTraced(Preset preset) { return preset == Preset::Direct || preset == Preset::Path; }

float effectiveScale(float cvarValue, Preset preset) {
  if (std::isfinite(cvarValue) && cvarValue > 0.0f) return std::clamp(cvarValue, 0.1f, 1.0f);
  return isRealTimeTraced(preset) ? 0.35f : 0.5f;
}

int effectiveTaau(int cvarValue, Preset preset) {
  if (cvarValue >= 0) return std::min(cvarValue, 2);
  return isRealTimeTraced(preset) ? 1 : 0;
}

float effectiveTaauSize(float cvarValue) {
  return std::isfinite(cvarValue) ? std::clamp(cvarValue, 0.25f, 1.0f) : 1.0f;
}

std::array<uint32_t, 2> taauOutputSize(uint32_t viewWidth, uint32_t viewHeight, uint32_t tracedWidth,
                                       uint32_t tracedHeight, float taauSize) {
  const auto side = [&](uint32_t view, uint32_t traced) {
    const auto scaled = static_cast<uint32_t>(std::lround(static_cast<double>(view) * taauSize));
    return std::max(traced, std::min(view, scaled));
  };
  return {side(viewWidth, tracedWidth), side(viewHeight, tracedHeight)};
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
  spp_ = engine.cvar("r_pt_spp", "1", CVAR_ARCHIVE, "Samples per pixel per frame (1..4096)");
  if (spp_ != nullptr) ri.Cvar_CheckRange(spp_, 1, 4096, 1);
  bounces_ = engine.cvar("r_pt_bounces", "2", CVAR_ARCHIVE, "Maximum path bounces (0..16)");
  if (bounces_ != nullptr) ri.Cvar_CheckRange(bounces_, 0, 16, 1);
  scale_ = engine.cvar("r_pt_scale", "0", CVAR_ARCHIVE,
                       "Internal resolution as a fraction of the window (0.1..1; 0 = the preset's: 0.35 for direct "
                       "and path, 0.5 for lightmap and reference)");
  if (scale_ != nullptr) ri.Cvar_CheckRange(scale_, 0.0f, 1.0f, 0);
  threads_ = engine.cvar("r_pt_threads", "0", CVAR_ARCHIVE | CVAR_LATCH,
                         "Render threads (0 = all cores); applies after vid_restart");
  if (threads_ != nullptr) ri.Cvar_CheckRange(threads_, 0, 256, 1);
  seed_ = engine.cvar("r_pt_seed", "0", 0, "Random seed of the sampler");
  stats_ = engine.cvar("r_pt_stats", "0", 0,
                       "Print traced views per second and milliseconds per traced frame");
  denoise_ = engine.cvar("r_pt_denoise", "1", CVAR_ARCHIVE,
                         "Edge-aware denoiser on the direct and path presets (0 = raw samples)");
  if (denoise_ != nullptr) ri.Cvar_CheckRange(denoise_, 0, 1, 1);
  // The stock picture cvars, with the stock defaults and flags (tr_init.c R_Register).
  gamma_ = engine.cvar("r_gamma", "1", CVAR_ARCHIVE, "Display gamma (menu brightness), 0.5..3");
  // r_picmip: 1, the default of the engine this module plays in (Debian's ioquake3 1.36+u20221123
  // opengl1 prints "picmip: 1" without any config; later ioquake3 releases default to 0).
  picmip_ = engine.cvar("r_picmip", "1", CVAR_ARCHIVE | CVAR_LATCH,
                        "Halve world and model textures this many times (0..16)");
  if (picmip_ != nullptr) ri.Cvar_CheckRange(picmip_, 0, 16, 1);
  dynamicLight_ = engine.cvar("r_dynamiclight", "1", CVAR_ARCHIVE,
                              "Dynamic lights (explosions, shots, muzzle flashes, powerups) in every preset, as "
                              "stock (0 = none)");
  overBrightBits_ = engine.cvar("r_overBrightBits", "1", CVAR_ARCHIVE | CVAR_LATCH,
                                "Display overbright bits (stock: with hardware gamma in fullscreen only)");
  mapOverBrightBits_ = engine.cvar("r_mapOverBrightBits", "2", CVAR_LATCH,
                                   "Lightmaps and baked vertex light are brightened by 2^(this - display bits)");
  intensity_ = engine.cvar("r_intensity", "1", CVAR_LATCH, "Multiplies world and model texture colours (>= 1)");
  textureMode_ = engine.cvar("r_textureMode", "GL_LINEAR_MIPMAP_NEAREST", CVAR_ARCHIVE,
                             "Texture filtering of the lightmap look: GL_NEAREST, GL_LINEAR, "
                             "GL_{NEAREST,LINEAR}_MIPMAP_{NEAREST,LINEAR}");
  flares_ = engine.cvar("r_flares", "0", CVAR_ARCHIVE, "Light flares of the map's flare surfaces");
  flareSize_ = engine.cvar("r_flareSize", "40", CVAR_CHEAT, "Flare size in pixels of a 640-wide view");
  flareFade_ = engine.cvar("r_flareFade", "7", CVAR_CHEAT, "Flare fade in or out: full range per 1/this seconds");
  flareCoeff_ = engine.cvar("r_flareCoeff", "150", CVAR_CHEAT, "Flare intensity falloff with distance (0 = 150)");
  temporal_ = engine.cvar("r_pt_temporal", "1", CVAR_ARCHIVE,
                          "Temporal accumulation (reprojected history) on the direct and path presets (0 = off)");
  if (temporal_ != nullptr) ri.Cvar_CheckRange(temporal_, 0, 1, 1);
  gradients_ = engine.cvar("r_pt_gradients", "6", CVAR_ARCHIVE,
                           "With r_pt_temporal: temporal gradients drop the history where the lighting changed; one of "
                           "last frame's samples per N x N pixels is traced again (N = 2..8; 0 = off)");
  if (gradients_ != nullptr) ri.Cvar_CheckRange(gradients_, 0, 8, 1);
  taau_ = engine.cvar("r_pt_taau", "-1", CVAR_ARCHIVE,
                      "Temporal anti-aliasing and upscaling of the traced world view to the window: 0 = off "
                      "(bilinear stretch), 1 = when r_pt_scale < 1, 2 = always, -1 = the preset's (1 for direct "
                      "and path, 0 for lightmap and reference)");
  if (taau_ != nullptr) ri.Cvar_CheckRange(taau_, -1, 2, 1);
  taauSize_ = engine.cvar("r_pt_taau_size", "1", CVAR_ARCHIVE,
                          "With r_pt_taau: the size TAAU resolves the world view to, as a fraction of the window "
                          "(0.25..1), stretched to the window after (0.5: a quarter of the resolve's cost)");
  if (taauSize_ != nullptr) ri.Cvar_CheckRange(taauSize_, 0.25f, 1.0f, 0);
  fps_ = engine.cvar("r_pt_fps", "0", CVAR_ARCHIVE,
                     "Dynamic resolution: frames per second to aim at by moving the traced world view's scale "
                     "between r_pt_scale_min and 1 (0 = off: r_pt_scale as set)");
  if (fps_ != nullptr) ri.Cvar_CheckRange(fps_, 0, 1000, 0);
  scaleMin_ = engine.cvar("r_pt_scale_min", "0.35", CVAR_ARCHIVE, "Least scale dynamic resolution (r_pt_fps) may pick (0.1..1)");
  if (scaleMin_ != nullptr) ri.Cvar_CheckRange(scaleMin_, 0.1f, 1.0f, 0);
  restir_ = engine.cvar("r_pt_restir", "0", CVAR_ARCHIVE,
                        "Direct light by spatiotemporal reservoir resampling (ReSTIR) on the direct and path presets (0 = off)");
  if (restir_ != nullptr) ri.Cvar_CheckRange(restir_, 0, 1, 1);
  bakedEnd_ = engine.cvar("r_pt_bake_end", "1", CVAR_ARCHIVE,
                          "Direct, path and reference: a path's last bounce that lands on a lightmapped or vertex-lit "
                          "surface takes the map's baked light there (its bounced light) instead of ending dark (0 = off)");
  if (bakedEnd_ != nullptr) ri.Cvar_CheckRange(bakedEnd_, 0, 1, 1);
  roulette_ = engine.cvar("r_pt_roulette", "1", CVAR_ARCHIVE,
                          "Direct, path and reference: scatterings after which Russian roulette may end a path "
                          "(1..16; 1: a bounce ray leaves a surface with the probability of its albedo)");
  if (roulette_ != nullptr) ri.Cvar_CheckRange(roulette_, 1, 16, 1);
  fireflies_ = engine.cvar("r_pt_fireflies", "1", CVAR_ARCHIVE,
                           "Spread fireflies (pixels far above their neighbourhood) over their neighbours before "
                           "the denoiser, keeping the frame's energy (0 = off)");
  if (fireflies_ != nullptr) ri.Cvar_CheckRange(fireflies_, 0, 1, 1);
  look_ = engine.cvar("r_pt_look", "stock", CVAR_ARCHIVE,
                      "How direct, path and reference show light: stock (as the lightmap: texture x light "
                      "in display values, light clamped to 1) | filmic (physical radiance, ACES curve)");
  captureExr_ = engine.cvar("r_pt_captureExr", "0", 0,
                            "screenshot NAME also writes NAME.exr: the world view's linear radiance (R, G, B) "
                            "and the variance of each pixel's mean luminance (variance.Y)");
  if (captureExr_ != nullptr) ri.Cvar_CheckRange(captureExr_, 0, 1, 1);
  pipeline_ = engine.cvar("r_pt_pipeline", "1", CVAR_ARCHIVE,
                          "1: the world view is traced while the game goes on and shown in the next frame, "
                          "under that frame's HUD (more fps, one frame of delay) | 0: each frame shows its own "
                          "world view (frames recorded as video always do)");
  if (pipeline_ != nullptr) ri.Cvar_CheckRange(pipeline_, 0, 1, 1);
  isa_ = engine.cvar("r_pt_isa", "auto", CVAR_ARCHIVE | CVAR_LATCH,
                     "Ray kernels: auto (the fastest this CPU has) | avx2 (the AVX2 kernels and 8-wide BVH "
                     "on a CPU with AVX-512, to measure what CPUs without it run); applies after vid_restart");
  lampVisibility_ = engine.cvar("r_pt_lamp_vis", "1", CVAR_ARCHIVE | CVAR_LATCH,
                                "Direct, path and reference: 1 = choose lamps that no shadow ray from the surfaces "
                                "around a point reached less often there (traced once per map, unbiased) | 0 = weigh "
                                "every lamp by its unshadowed light alone; applies after vid_restart");
  if (lampVisibility_ != nullptr) ri.Cvar_CheckRange(lampVisibility_, 0, 1, 1);
  clamp_ = engine.cvar("r_pt_clamp", "-1", 0,
                       "Clamp of each sample's radiance (0 = none, an unbiased mean); -1 = the preset's "
                       "(reference none, the others 10)");
}

bool Settings::dynamicLights() const { return dynamicLight_ == nullptr || dynamicLight_->integer != 0; }

VideoModeRequest Settings::videoMode() const {
  VideoModeRequest request;
  if (mode_ != nullptr) request.mode = mode_->integer;
  if (customWidth_ != nullptr) request.customWidth = customWidth_->integer;
  if (customHeight_ != nullptr) request.customHeight = customHeight_->integer;
  if (fullscreen_ != nullptr) request.fullscreen = fullscreen_->integer != 0;
  return request;
}

int PictureSettings::displayOverBrightBits() const { return fullscreen ? std::clamp(overBrightBits, 0, 2) : 0; }

int PictureSettings::lightShift() const { return std::clamp(mapOverBrightBits - displayOverBrightBits(), 0, 8); }

std::array<uint8_t, 256> gammaRamp(float gamma, int overbrightBits) {
  std::array<uint8_t, 256> ramp{};
  const int shift = std::clamp(overbrightBits, 0, 8);
  for (int i = 0; i < 256; ++i) {
    int value = i;
    if (gamma != 1.0f) value = static_cast<int>(255.0f * std::pow(float(i) / 255.0f, 1.0f / gamma) + 0.5f);
    ramp[size_t(i)] = static_cast<uint8_t>(std::clamp(value << shift, 0, 255));
  }
  return ramp;
}

bool isIdentityRamp(const std::array<uint8_t, 256>& ramp) {
  for (int i = 0; i < 256; ++i)
    if (ramp[size_t(i)] != i) return false;
  return true;
}

void applyIntensity(std::vector<uint8_t>& rgba, float intensity) {
  if (!(intensity > 1.0f)) return;
  std::array<uint8_t, 256> table{};
  for (int i = 0; i < 256; ++i) table[size_t(i)] = static_cast<uint8_t>(std::min(255, static_cast<int>(float(i) * intensity)));
  for (size_t p = 0; p + 3 < rgba.size(); p += 4)
    for (size_t c = 0; c < 3; ++c) rgba[p + c] = table[rgba[p + c]];
}

std::vector<uint8_t> picmipImage(const std::vector<uint8_t>& rgba, int& width, int& height, int times) {
  std::vector<uint8_t> image = rgba;
  for (int step = 0; step < times && (width > 1 || height > 1); ++step) {
    const int w = std::max(1, width / 2), h = std::max(1, height / 2);
    std::vector<uint8_t> half(size_t(w) * size_t(h) * 4);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 4; ++c) {
          int sum = 0;
          for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
              const int sx = std::min(width - 1, 2 * x + dx), sy = std::min(height - 1, 2 * y + dy);
              sum += image[(size_t(sy) * size_t(width) + size_t(sx)) * 4 + size_t(c)];
            }
          half[(size_t(y) * size_t(w) + size_t(x)) * 4 + size_t(c)] = static_cast<uint8_t>((sum + 2) / 4);
        }
    image = std::move(half);
    width = w;
    height = h;
  }
  return image;
}

PictureSettings Settings::picture(const Engine& engine) const {
  PictureSettings out;
  const auto& ri = engine.ri();
  if (gamma_ != nullptr && std::isfinite(gamma_->value)) {
    if (gamma_->value < 0.5f) ri.Cvar_Set("r_gamma", "0.5");
    else if (gamma_->value > 3.0f) ri.Cvar_Set("r_gamma", "3.0");
    out.gamma = std::clamp(gamma_->value, 0.5f, 3.0f);
  }
  if (picmip_ != nullptr) out.picmip = std::clamp(picmip_->integer, 0, 16);
  if (overBrightBits_ != nullptr) out.overBrightBits = overBrightBits_->integer;
  if (mapOverBrightBits_ != nullptr) out.mapOverBrightBits = mapOverBrightBits_->integer;
  if (intensity_ != nullptr && std::isfinite(intensity_->value)) {
    if (intensity_->value <= 1.0f && intensity_->value != 1.0f) ri.Cvar_Set("r_intensity", "1");
    out.intensity = std::max(1.0f, intensity_->value);
  }
  out.flares = flares_ != nullptr && flares_->integer != 0;
  const auto finiteOr = [](const q3abi::cvar_t* cvar, float fallback) {
    return cvar != nullptr && std::isfinite(cvar->value) ? cvar->value : fallback;
  };
  out.flare.size = finiteOr(flareSize_, 40.0f);
  out.flare.fade = finiteOr(flareFade_, 7.0f);
  out.flare.coeff = finiteOr(flareCoeff_, 150.0f);
  if (out.flare.coeff == 0.0f) out.flare.coeff = 150.0f;   // stock: 0 means the standard coefficient
  return out;
}

bool Settings::gammaChanged() const {
  if (gamma_ == nullptr || !gamma_->modified) return false;
  gamma_->modified = 0;
  return true;
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
  if (spp_ != nullptr) out.samplesPerPixel = std::clamp(spp_->integer, 1, 4096);
  if (bounces_ != nullptr) out.maxBounces = std::clamp(bounces_->integer, 0, 16);
  // r_pt_scale 0 and r_pt_taau -1, their defaults, stand for the preset's own.
  out.resolutionScale = effectiveScale(scale_ != nullptr ? scale_->value : 0.0f, out.preset);
  if (threads_ != nullptr) out.threads = std::clamp(threads_->integer, 0, 256);
  if (seed_ != nullptr) out.seed = static_cast<uint32_t>(seed_->integer);
  out.printStats = stats_ != nullptr && stats_->integer != 0;
  out.denoise = denoise_ == nullptr || denoise_->integer != 0;
  out.temporal = temporal_ == nullptr || temporal_->integer != 0;
  out.restir = restir_ != nullptr && restir_->integer != 0;
  // 1 reaches the renderer as it is: its gradients take blocks of at least 2 (GradientConfig).
  out.gradientStratum = gradients_ == nullptr ? 6u : static_cast<uint32_t>(std::clamp(gradients_->integer, 0, 8));
  out.bakedEnd = bakedEnd_ == nullptr || bakedEnd_->integer != 0;
  if (roulette_ != nullptr) out.rouletteStart = std::clamp(roulette_->integer, 1, 16);
  out.taau = effectiveTaau(taau_ != nullptr ? taau_->integer : -1, out.preset);
  out.taauSize = effectiveTaauSize(taauSize_ != nullptr ? taauSize_->value : 1.0f);
  if (fps_ != nullptr && std::isfinite(fps_->value)) out.targetFps = std::clamp(fps_->value, 0.0f, 1000.0f);
  if (scaleMin_ != nullptr && std::isfinite(scaleMin_->value)) out.minScale = std::clamp(scaleMin_->value, 0.1f, 1.0f);
  out.fireflies = fireflies_ == nullptr || fireflies_->integer != 0;
  out.stockLook = look_ == nullptr || look_->string == nullptr || normalizeName(look_->string) != "filmic";
  out.captureExr = captureExr_ != nullptr && captureExr_->integer != 0;
  out.pipeline = pipeline_ == nullptr || pipeline_->integer != 0;
  if (clamp_ != nullptr && std::isfinite(clamp_->value)) out.radianceClamp = clamp_->value < 0.0f ? -1.0f : clamp_->value;
  out.lampVisibility = lampVisibility_ == nullptr || lampVisibility_->integer != 0;
  if (isa_ != nullptr && isa_->string != nullptr) {
    const std::string isa = normalizeName(isa_->string);
    out.avx2Kernels = isa == "avx2";
    if (isa != "avx2" && isa != "auto" && isa_->modified)
      engine.warn(std::string("r_pt_isa '") + isa_->string + "' unknown: auto used (auto or avx2)");
    isa_->modified = 0;
  }
  // Parsed when it changes, as stock applies it (the name outgrows std::string's inline buffer:
  // parsing it every frame would allocate in the steady state).
  if (textureMode_ != nullptr && textureMode_->string != nullptr && (textureMode_->modified || !textureFilterRead_)) {
    bool known = true;
    textureFilter_ = parseTextureMode(textureMode_->string, known);
    if (!known)
      engine.warn(std::string("r_textureMode '") + textureMode_->string + "' unknown: GL_LINEAR_MIPMAP_NEAREST used");
    textureMode_->modified = 0;
    textureFilterRead_ = true;
  }
  out.textureFilter = textureFilter_;
  return out;
}

}  // namespace glue
