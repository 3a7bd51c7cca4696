// Module lifecycle and registration: BeginRegistration / Shutdown, shaders, models, skins,
// fonts, the world, RemapShader, entity tokens, model queries.
#include "port/engine_glue/module.h"

#include <cstdlib>

#include <SDL.h>

#include <cmath>
#include <cstring>

#include "port/engine_glue/views.h"
#include "port/q3formats/common/format_error.h"

namespace glue {

Module::Module(const q3abi::refimport_t& ri) : engine_(ri) {}

Module::~Module() {
  // Normally Shutdown(1) has released everything; this covers an engine that never called it.
  if (registered_ || window_.isOpen()) {
    try {
      shutdown(true);
    } catch (...) {
    }
  }
}

void Module::shutdown(bool destroyWindow) {
  removeCommands();
  pendingShots_.clear();
  scene_.clear();
  if (views_) views_->clearWorld();   // first: a world view may still be traced
  shownFrame_ = UINT64_MAX;           // nothing of this world is shown again
  flareQuads_.clear();
  world_.reset();
  if (modelViews_) modelViews_->clearWorld();   // its materials name this registration's shaders
  models_.clear();
  fonts_.clear();
  if (window_.isOpen()) shaders_.clear();   // GL textures need the context
  images_.clear();
  registered_ = false;
  frameOpen_ = false;
  if (destroyWindow) {
    views_.reset();
    modelViews_.reset();
    if (window_.isOpen()) {
      overlay_.release();
      engine_.ri().IN_Shutdown();
      window_.close();
    }
  }
}

void Module::ensureWindow(q3abi::glconfig_t* config) {
  if (!window_.isOpen()) {
    window_.open(settings_.videoMode(), glconfig_);
    engine_.print(q3abi::PRINT_ALL, "pathtracer: %dx%d window, GL %s (%s)\n", glconfig_.vidWidth,
                  glconfig_.vidHeight, glconfig_.version_string, glconfig_.renderer_string);
    engine_.ri().IN_Init(window_.sdlWindow());
  }
  if (config != nullptr) *config = glconfig_;
}

PictureSettings Module::picture() const {
  PictureSettings out = settings_.picture(engine_);
  out.fullscreen = glconfig_.isFullscreen != 0;
  return out;
}

void Module::updateDisplayRamp() {
  displayRamp_ = gammaRamp(settings_.picture(engine_).gamma, 0);
  rampIsIdentity_ = isIdentityRamp(displayRamp_);
}

namespace {

/// Stock opengl1 draws its noise lattice (256 values and 256 permutation entries, tr_noise.c
/// R_NoiseInit) from the C library's rand() each time it starts (RE_BeginRegistration ->
/// R_Init): 512 draws. The game's native cgame draws its random effects (explosion rotations,
/// smoke puffs, brass, the HUD head's turns) from the same sequence, so the module makes as many
/// draws at the same point: under one seed a demo's random effects are those of opengl1. The
/// values are not used (the glue's wave noise is its own, shader_time.h).
void drawLikeTheStockRendererStart() {
  for (int i = 0; i < kStockRendererStartDraws; ++i) (void)std::rand();
}

}  // namespace

void Module::beginRegistration(q3abi::glconfig_t* config) {
  settings_.registerCvars(engine_);
  // Re-initialise fully (the engine calls Shutdown(0) before every map).
  if (registered_) shutdown(false);
  ensureWindow(config);
  drawLikeTheStockRendererStart();
  updateDisplayRamp();
  const TracerSettings tracer = settings_.tracer(engine_);
  if (!views_)
    views_ = std::make_unique<ViewRenderer>(engine_, tracer.threads, tracer.avx2Kernels, tracer.lampVisibility);
  if (!modelViews_)
    modelViews_ = std::make_unique<ViewRenderer>(engine_, tracer.threads, tracer.avx2Kernels, tracer.lampVisibility);
  views_->setPicture(picture());
  modelViews_->setPicture(picture());
  scripts_.load(engine_);
  engine_.print(q3abi::PRINT_DEVELOPER, "pathtracer: %zu shaders in scripts\n", scripts_.size());
  addCommands();
  registered_ = true;
}

q3abi::qhandle_t Module::registerShader(const char* name) {
  if (name == nullptr) return 0;
  return shaders_.registerShader(engine_, scripts_, images_, name, true);
}

q3abi::qhandle_t Module::registerShaderNoMip(const char* name) {
  if (name == nullptr) return 0;
  return shaders_.registerShader(engine_, scripts_, images_, name, false);
}

q3abi::qhandle_t Module::registerModel(const char* name) {
  if (name == nullptr) return 0;
  const int submodels = world_ ? static_cast<int>(world_->brushModels().size()) : 0;
  const q3abi::qhandle_t handle = models_.registerModel(engine_, name, submodels);
  // Register the MD3's own shaders now, like the stock renderer does at load.
  if (const ModelEntry* entry = models_.model(handle); entry != nullptr && entry->kind == ModelKind::Md3)
    for (const auto& lod : entry->lods)
      for (const q3::Md3Surface& surface : lod->surfaces)
        for (const q3::Md3Shader& shader : surface.shaders)
          if (!shader.name.empty()) registerShader(shader.name.c_str());
  return handle;
}

q3abi::qhandle_t Module::registerSkin(const char* name) {
  if (name == nullptr || name[0] == '\0') return 0;
  return models_.registerSkin(engine_, name,
                              [this](const std::string& shader) { return registerShader(shader.c_str()); });
}

void Module::loadWorld(const char* name) {
  if (name == nullptr) throw DropError("LoadWorld: no map name");
  if (world_) throw DropError("LoadWorld: a world is already loaded (missing Shutdown)");
  auto bytes = engine_.readFile(name);
  if (!bytes) throw DropError(std::string("LoadWorld: ") + name + " not found");
  try {
    world_ = std::make_unique<World>(*bytes, name, scripts_.shared());
  } catch (const q3::FormatError& error) {
    throw DropError(std::string("LoadWorld: ") + error.what());
  }
  if (views_) {
    try {
      views_->setPicture(picture());
      views_->loadWorld(*world_, scripts_, images_);
    } catch (const std::exception& error) {
      world_.reset();
      throw DropError(std::string("LoadWorld: ") + name + ": " + error.what());
    }
  }
  worldFlares_.clear();
  const q3::BspFile& bsp = world_->bsp();
  if (!bsp.models.empty()) {
    const auto first = static_cast<size_t>(std::max(0, bsp.models[0].firstSurface));
    const size_t end = std::min(bsp.surfaces.size(), first + static_cast<size_t>(std::max(0, bsp.models[0].numSurfaces)));
    for (size_t i = first; i < end; ++i) {
      const q3::BspSurface& s = bsp.surfaces[i];
      if (s.type == q3::SurfaceType::Flare) worldFlares_.push_back({s.lightmapOrigin, s.lightmapVecs[0], s.lightmapVecs[2]});
    }
  }
  flareTracker_.reset(worldFlares_.size());
  flareShader_ = registerShader("flareShader");
  engine_.print(q3abi::PRINT_ALL, "pathtracer: loaded %s (%zu brush models, %zu flares)\n", name,
                world_->brushModels().size(), worldFlares_.size());
}

void Module::setWorldVisData(const q3abi::byte*) {
  // The client never calls this (measured); our visibility comes from the BSP itself.
}

void Module::endRegistration() {
  // Every model, skin and shader of the map is registered now: what the first view would do once
  // for the whole map (materials, textures, the world's look and lights) is done here, in the
  // loading screen, instead of in the first frame of play; then a throw-away world view makes
  // the frame buffers, and the overlay the GL state and storage, the first frame would wait for.
  // What fails here fails again, and is reported, where the first view does it.
  const TracerSettings tracer = settings_.tracer(engine_);
  const auto prepare = [&](ViewRenderer* views, bool withWorld) {
    if (views == nullptr) return;
    try {
      views->prepareForPlay(shaders_, tracer, withWorld);
    } catch (const std::exception& error) {
      engine_.print(q3abi::PRINT_DEVELOPER, "pathtracer: EndRegistration: %s\n", error.what());
    }
  };
  if (world_) prepare(views_.get(), true);
  prepare(modelViews_.get(), false);
  if (world_ && views_ != nullptr && window_.isOpen()) {
    try {
      const auto [width, height] = views_->warmUp(tracer, window_.width(), window_.height());
      overlay_.prepareForPlay(width, height);
    } catch (const std::exception& error) {
      engine_.print(q3abi::PRINT_DEVELOPER, "pathtracer: EndRegistration: %s\n", error.what());
    }
  }
}

int Module::lerpTag(q3abi::orientation_t* tag, q3abi::qhandle_t model, int startFrame,
                    int endFrame, float frac, const char* tagName) {
  if (tag == nullptr) return 0;
  q3abi::orientation_t result{};
  const bool found = models_.lerpTag(result, model, startFrame, endFrame, frac,
                                     tagName != nullptr ? tagName : "");
  *tag = result;
  return found ? 1 : 0;
}

void Module::modelBounds(q3abi::qhandle_t model, float* mins, float* maxs) {
  if (mins == nullptr || maxs == nullptr) return;
  glm::vec3 lo(0.0f), hi(0.0f);
  if (!models_.md3Bounds(model, lo, hi)) {
    const ModelEntry* entry = models_.model(model);
    if (entry != nullptr && entry->kind == ModelKind::Brush && world_ &&
        entry->brushIndex < static_cast<int>(world_->brushModels().size())) {
      lo = world_->brushModels()[entry->brushIndex].mins;
      hi = world_->brushModels()[entry->brushIndex].maxs;
    }
  }
  for (int i = 0; i < 3; ++i) {
    mins[i] = lo[i];
    maxs[i] = hi[i];
  }
}

void Module::registerFont(const char* fontName, int pointSize, q3abi::fontInfo_t* font) {
  if (font == nullptr) return;
  if (pointSize <= 0) pointSize = 12;
  char datName[q3abi::kMaxQPath];
  std::snprintf(datName, sizeof datName, "fonts/fontImage_%i.dat", pointSize);
  if (const auto cached = fonts_.find(datName); cached != fonts_.end()) {
    *font = cached->second;
    return;
  }
  q3abi::fontInfo_t result{};
  const auto bytes = engine_.readFile(datName);
  if (bytes && bytes->size() == sizeof(q3abi::fontInfo_t)) {
    // The pre-rendered layout is the struct itself, little-endian (ints, floats, names).
    std::memcpy(&result, bytes->data(), sizeof result);
    for (auto& glyph : result.glyphs) {
      glyph.shaderName[sizeof glyph.shaderName - 1] = '\0';
      glyph.glyph = glyph.shaderName[0] != '\0' ? registerShaderNoMip(glyph.shaderName) : 0;
    }
    if (!std::isfinite(result.glyphScale) || result.glyphScale <= 0.0f)
      result.glyphScale = 48.0f / static_cast<float>(pointSize);
  } else {
    engine_.print(q3abi::PRINT_DEVELOPER,
                  "pathtracer: no %s for %s: glyphs from gfx/2d/bigchars\n", datName,
                  fontName != nullptr ? fontName : "?");
    fillFallbackFont(result, pointSize);
  }
  std::snprintf(result.name, sizeof result.name, "%s", datName);
  fonts_[datName] = result;
  *font = result;
}

void Module::fillFallbackFont(q3abi::fontInfo_t& font, int pointSize) {
  // The console's 16x16-cell bitmap font, laid out as a monospaced glyph font.
  const q3abi::qhandle_t sheet = registerShaderNoMip("gfx/2d/bigchars");
  constexpr float kCell = 1.0f / 16.0f;
  for (int c = 0; c < q3abi::kGlyphsPerFont; ++c) {
    q3abi::glyphInfo_t& g = font.glyphs[c];
    g = {};
    if (c < 32 || c > 126) continue;
    g.height = pointSize;
    g.top = pointSize;
    g.bottom = 0;
    g.pitch = pointSize;
    g.xSkip = pointSize;
    g.imageWidth = pointSize;
    g.imageHeight = pointSize;
    g.s = static_cast<float>(c % 16) * kCell;
    g.t = static_cast<float>(c / 16) * kCell;
    g.s2 = g.s + kCell;
    g.t2 = g.t + kCell;
    g.glyph = sheet;
    std::snprintf(g.shaderName, sizeof g.shaderName, "gfx/2d/bigchars");
  }
  font.glyphScale = 48.0f / static_cast<float>(pointSize);
}

void Module::remapShader(const char* oldShader, const char* newShader, const char* timeOffset) {
  if (oldShader == nullptr || newShader == nullptr) return;
  const float offset = timeOffset != nullptr ? std::strtof(timeOffset, nullptr) : 0.0f;
  shaders_.remap(engine_, scripts_, images_, oldShader, newShader,
                 std::isfinite(offset) ? offset : 0.0f);
  if (views_) views_->shadersChanged();
  if (modelViews_) modelViews_->shadersChanged();
}

bool Module::getEntityToken(char* buffer, int size) {
  if (!world_) {
    if (buffer != nullptr && size > 0) buffer[0] = '\0';
    return false;
  }
  return world_->nextEntityToken(buffer, size);
}

double Module::seconds() const { return engine_.milliseconds() * 0.001; }

}  // namespace glue
