#include "port/engine_glue/shader_animation.h"

#include <cmath>

#include "port/engine_glue/shader_scripts.h"
#include "port/engine_glue/stock_look.h"   // byteToLinear
#include "port/q3formats/shader/material.h"
#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/shader/shader_time.h"
#include "port/q3formats/world/world_scene.h"
#include "port/scene_bridge/scene_bridge.h"
#include "renderer/scene/renderer.h"

namespace glue {
namespace {

/// The grey byte a wave level in [0, 1] becomes (stock truncates), as linear light.
float greyByteToLinear(float level) { return byteToLinear(std::floor(255.0f * level)); }

bool sameLook(const pa::MaterialDesc& a, const pa::MaterialDesc& b) {
  return a.uvTransform == b.uvTransform && a.uvWobble == b.uvWobble && a.baseColor == b.baseColor &&
         a.emission == b.emission && a.seenEmission == b.seenEmission && a.baseTexture == b.baseTexture && a.emissiveTexture == b.emissiveTexture &&
         a.emissiveOwnUv == b.emissiveOwnUv && a.emissiveUvTransform == b.emissiveUvTransform;
}

}  // namespace

bool StageMotion::timeDependent() const {
  const bool rgbWaves = rgbGen == q3::RgbGen::Wave && (rgbWave.amplitude != 0 || rgbWave.func == q3::WaveFunc::Noise);
  const bool alphaWaves = alphaGen == q3::AlphaGen::Wave && alphaWave.amplitude != 0;
  return q3::tcModsAnimate(tcMods) || q3::tcModsAnimate(glowTcMods) || rgbWaves || alphaWaves ||
         (glowWaves && glowWave.amplitude != 0);
}

StageMotion motionOf(const ShaderLook& look) {
  StageMotion motion;
  motion.tcMods = look.tcMods;
  motion.rgbGen = look.rgbGen;
  motion.rgbWave = look.rgbWave;
  motion.alphaGen = look.alphaGen;
  motion.alphaWave = look.alphaWave;
  return motion;
}

void applyTcMods(const std::vector<q3::TcMod>& tcMods, double seconds, pa::MaterialDesc& desc,
                 std::array<float, 2> entityScroll) {
  const q3::TcModsAt at = q3::tcModsAt(tcMods, seconds, entityScroll);
  const q3::UvAffine& m = at.affine;
  desc.uvTransform = glm::mat3x2(glm::vec2(m.a, m.c), glm::vec2(m.b, m.d), glm::vec2(m.tx, m.ty));
  desc.uvWobble = pa::UvWobble{};
  if (at.wobble.amplitude != 0.0f) {
    const q3::UvAffine& after = at.wobble.after;
    desc.uvWobble.amplitude = at.wobble.amplitude;
    desc.uvWobble.phase = static_cast<float>(at.wobble.phase - std::floor(at.wobble.phase));
    // Stock turb: s reads (x + z) / 1024, t reads y / 1024 cycles.
    desc.uvWobble.axisU = glm::vec3(1.0f / 1024.0f, 0.0f, 1.0f / 1024.0f);
    desc.uvWobble.axisV = glm::vec3(0.0f, 1.0f / 1024.0f, 0.0f);
    desc.uvWobble.linear = glm::mat2(glm::vec2(after.a, after.c), glm::vec2(after.b, after.d));
  }
}

pa::MaterialDesc materialAt(const StageMotion& motion, double seconds, const pa::MaterialDesc& still,
                            std::array<float, 2> entityScroll) {
  pa::MaterialDesc desc = still;
  if (!motion.tcMods.empty()) applyTcMods(motion.tcMods, seconds, desc, entityScroll);
  if (motion.rgbGen == q3::RgbGen::Wave) {
    const float grey = greyByteToLinear(q3::rgbWaveAt(motion.rgbWave, seconds));
    desc.baseColor = glm::vec4(glm::vec3(still.baseColor) * grey, still.baseColor.a);
  }
  if (motion.alphaGen == q3::AlphaGen::Wave) {
    const float alpha = q3::alphaWaveAt(motion.alphaWave, seconds);
    if (desc.alphaMode == pa::AlphaMode::Additive && desc.stock.layerBlend == pa::LayerBlend::Over)
      // Premultiplied, in display values as the layer is composed: the colour by the linearised
      // alpha (lin(c) lin(a) ~ lin(c a)), the coverage by the alpha itself.
      desc.baseColor = glm::vec4(glm::vec3(desc.baseColor) * byteToLinear(alpha * 255.0f), desc.baseColor.a * alpha);
    else
      desc.baseColor.a *= alpha;
  }
  if (motion.glowWaves) {
    const float level = greyByteToLinear(q3::rgbWaveAt(motion.glowWave, seconds));
    desc.emission = still.emission * level;
    if (still.seenEmission.x >= 0.0f) desc.seenEmission = still.seenEmission * level;
  }
  if (motion.glowOwnUv && still.emissiveTexture != pa::kNoId) {
    const q3::UvAffine m = q3::tcModsAt(motion.glowTcMods, seconds, entityScroll).affine;
    desc.emissiveOwnUv = true;
    desc.emissiveUvTransform = glm::mat3x2(glm::vec2(m.a, m.c), glm::vec2(m.b, m.d), glm::vec2(m.tx, m.ty));
  }
  return desc;
}

pa::MaterialId MovingMaterialPool::get(const StageMotion& motion, const pa::MaterialDesc& still, double seconds,
                                       std::array<float, 2> scroll, uint64_t view, pa::Renderer& renderer,
                                       size_t& updates) {
  for (const Slot& slot : slots_)
    if (slot.view == view && slot.seconds == seconds && slot.scroll == scroll) return slot.id;
  for (Slot& slot : slots_) {
    if (slot.view == view) continue;
    if (slot.seconds != seconds || slot.scroll != scroll) {
      renderer.setMaterial(slot.id, materialAt(motion, seconds, still, scroll));
      ++updates;
    }
    slot.seconds = seconds;
    slot.scroll = scroll;
    slot.view = view;
    return slot.id;
  }
  const pa::MaterialId id = renderer.addMaterial(materialAt(motion, seconds, still, scroll));
  slots_.push_back(Slot{id, seconds, scroll, view});
  return id;
}

void WorldAnimation::prepare(const q3::WorldScene& scene, const q3::ShaderLibrary& library,
                             const pa::bridge::WorldHandles& world, pa::Renderer& renderer,
                             const FrameTexture& frameTexture) {
  entries_.clear();
  seconds_ = 0.0;
  for (const auto& [key, id] : world.materials) {
    const q3::WorldMaterial& m = scene.materials.at(key.first);
    if (!m.fromScript || m.sky) continue;
    const q3::ShaderDef* shader = library.find(m.shaderName);
    if (shader == nullptr) continue;
    const q3::MaterialInfo info = q3::deriveMaterial(*shader);
    Entry entry;
    entry.id = id;
    entry.motion.tcMods = info.uvAnimation;
    entry.motion.rgbGen = info.baseRgbGen;
    entry.motion.rgbWave = info.baseRgbWave;
    entry.motion.alphaGen = info.baseAlphaGen;
    entry.motion.alphaWave = info.baseAlphaWave;
    entry.motion.glowWaves = info.glowWaves && m.emissiveTexture >= 0;
    entry.motion.glowWave = info.glowWave;
    if (m.emissiveTexture >= 0 && !info.glowTextures.empty()) {
      entry.motion.glowTcMods = info.glowTcMods;
      entry.motion.glowOwnUv = !q3::sameTcMods(info.glowTcMods, info.uvAnimation);
    }
    entry.still = pa::bridge::materialDesc(scene, world, key.first, key.second);
    entry.stillBase = entry.still.baseTexture;
    // A shiny trim's base is the texture it adds over its chrome, on the mesh uvs (scene_bridge):
    // the chrome stage's tcMods and colour waves are not that texture's.
    if (m.baseReflects && entry.still.baseTexCoords == pa::TexCoordSource::Mesh) {
      entry.motion.tcMods.clear();
      entry.motion.rgbGen = q3::RgbGen::Identity;
      entry.motion.alphaGen = q3::AlphaGen::Identity;
    }
    if (info.animFrames.size() > 1 && info.animFrequency > 0.0f) {
      for (const std::string& frame : info.animFrames) {
        const pa::TextureId texture = frameTexture(frame, info.clampUv);
        entry.frames.push_back(texture != pa::kNoId ? texture : entry.stillBase);
      }
      entry.frameRate = info.animFrequency;
    }
    entry.timeDependent = entry.motion.timeDependent() || !entry.frames.empty();
    if (!entry.timeDependent && !entry.motion.any()) continue;
    show(entry, 0.0, renderer, true);
    entries_.push_back(std::move(entry));
  }
}

pa::MaterialDesc WorldAnimation::lookAt(const Entry& entry, double seconds) const {
  pa::MaterialDesc desc = materialAt(entry.motion, seconds, entry.still);
  if (!entry.frames.empty() && entry.still.baseTexture == entry.stillBase) {
    const pa::TextureId frame = entry.frames[q3::animMapFrame(entry.frames.size(), entry.frameRate, seconds)];
    desc.baseTexture = frame;
    // An additive animMap base that is its own glow glows with the frame it shows.
    if (entry.still.emissiveTexture == entry.stillBase) desc.emissiveTexture = frame;
  }
  return desc;
}

void WorldAnimation::show(Entry& entry, double seconds, pa::Renderer& renderer, bool force) {
  pa::MaterialDesc desc = lookAt(entry, seconds);
  if (!force && sameLook(desc, entry.shown)) return;
  renderer.setMaterial(entry.id, desc);
  entry.shown = std::move(desc);
  ++lastUpdates_;
}

void WorldAnimation::setMaterial(pa::MaterialId id, const pa::MaterialDesc& still, pa::Renderer& renderer) {
  for (Entry& entry : entries_) {
    if (entry.id != id) continue;
    entry.still = still;
    show(entry, seconds_, renderer, true);
    return;
  }
  renderer.setMaterial(id, still);
}

void WorldAnimation::update(double seconds, pa::Renderer& renderer) {
  lastUpdates_ = 0;
  if (seconds == seconds_) return;
  seconds_ = seconds;
  for (Entry& entry : entries_)
    if (entry.timeDependent) show(entry, seconds, renderer, false);
}

size_t WorldAnimation::animatedCount() const {
  size_t n = 0;
  for (const Entry& entry : entries_) n += entry.timeDependent ? 1 : 0;
  return n;
}

}  // namespace glue
