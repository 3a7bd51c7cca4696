#pragma once
// Shader animation in traced views: the time-dependent parts of a stage (tcMods, animMap frames,
// rgbGen / alphaGen wave, a glow stage's rgbGen wave) written into renderer materials at a view's
// shader time (refdef time; minus the entity's shaderTime for entities). Only materials whose
// shaders animate are touched, and only when what they show changes.
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "port/q3formats/shader/shader_types.h"
#include "renderer/scene/scene_types.h"

namespace q3 {
class ShaderLibrary;
struct WorldScene;
}  // namespace q3

namespace pa {
class Renderer;
namespace bridge {
struct WorldHandles;
}
}  // namespace pa

namespace glue {

struct ShaderLook;

/// The animated parts of one stage as the script gives them.
struct StageMotion {
  std::vector<q3::TcMod> tcMods;
  q3::RgbGen rgbGen = q3::RgbGen::Default;
  q3::WaveForm rgbWave;
  q3::AlphaGen alphaGen = q3::AlphaGen::Default;
  q3::WaveForm alphaWave;
  bool glowWaves = false;       ///< The material's emission follows glowWave (a glow stage's rgbGen wave).
  q3::WaveForm glowWave;
  std::vector<q3::TcMod> glowTcMods;   ///< The glow stage's own tcMods (its emissive texture's uvs).
  /// The glow is a stage of its own whose tcMods differ from the base's: its emissive texture is
  /// read at the mesh uvs through glowTcMods, even when it is the base's image (lava: one image at
  /// two scales).
  bool glowOwnUv = false;

  /// True when anything here changes with time.
  bool timeDependent() const;
  /// True when the material's uvs or colours differ from the still look at some time (a static
  /// tcMod transform or scale included).
  bool any() const { return !tcMods.empty() || !glowTcMods.empty() || glowOwnUv || timeDependent(); }
};

/// The motion of a drawable look's stage (its tcMods and waves).
StageMotion motionOf(const ShaderLook& look);

/// The renderer's uv transform and wobble of tcMods at `seconds` (entityTranslate scrolls by
/// `entityScroll`), written into `desc`. The wobble is the stock turb: object-space positions.
void applyTcMods(const std::vector<q3::TcMod>& tcMods, double seconds, pa::MaterialDesc& desc,
                 std::array<float, 2> entityScroll = {0, 0});

/// `still` (the material as drawn without animation) moved to shader time `seconds`: tcMods
/// replace its uv transform; rgbGen wave scales its colour by the wave's grey byte (linearised,
/// as stock multiplies bytes in gamma space); alphaGen wave sets its alpha (the whole colour for
/// premultiplied layers, LayerBlend::Over); a glow wave scales its emission; with glowOwnUv the
/// glow tcMods move its emissive texture on its own uvs (their turb is left out).
pa::MaterialDesc materialAt(const StageMotion& motion, double seconds, const pa::MaterialDesc& still,
                            std::array<float, 2> entityScroll = {0, 0});

/// Renderer materials of one animated look: one per shader time in use within a view (entities'
/// shaderTime differ), reused by later views.
class MovingMaterialPool {
 public:
  /// The material showing `still` moved by `motion` to (`seconds`, `scroll`) in view number
  /// `view`: one that already shows it in this view, else one this view has not used (replaced,
  /// counted in `updates`), else a new one.
  pa::MaterialId get(const StageMotion& motion, const pa::MaterialDesc& still, double seconds,
                     std::array<float, 2> scroll, uint64_t view, pa::Renderer& renderer, size_t& updates);

 private:
  struct Slot {
    pa::MaterialId id = pa::kNoId;
    double seconds = 0.0;
    std::array<float, 2> scroll{};
    uint64_t view = 0;   ///< The view that last used it.
  };
  std::vector<Slot> slots_;
};

/// The world's animated materials (world and brush models, at refdef time).
class WorldAnimation {
 public:
  /// Renderer texture of an image path (clampMap when `clamp`); kNoId when it cannot be read.
  using FrameTexture = std::function<pa::TextureId(const std::string& path, bool clamp)>;

  /// Finds the world materials whose base stage animates, or whose tcMods transform uvs, and
  /// writes their time-0 look; animMap frames are read through `frameTexture`.
  void prepare(const q3::WorldScene& scene, const q3::ShaderLibrary& library, const pa::bridge::WorldHandles& world,
               pa::Renderer& renderer, const FrameTexture& frameTexture);
  /// Sets a world material's still look: animated ones keep it and show it moved to the last
  /// update's time; others are set as given.
  void setMaterial(pa::MaterialId id, const pa::MaterialDesc& still, pa::Renderer& renderer);
  /// Moves every time-dependent material to shader time `seconds` (setMaterial only for those
  /// whose look changed).
  void update(double seconds, pa::Renderer& renderer);
  /// Number of world materials that change with time.
  size_t animatedCount() const;
  /// Number of setMaterial calls made by the last update.
  size_t lastUpdates() const { return lastUpdates_; }
  /// Forgets everything (a new map).
  void clear() { *this = WorldAnimation{}; }

 private:
  struct Entry {
    pa::MaterialId id = pa::kNoId;
    StageMotion motion;
    bool timeDependent = false;
    std::vector<pa::TextureId> frames;   ///< animMap frames (empty: the still base texture)
    float frameRate = 0;
    pa::TextureId stillBase = pa::kNoId; ///< The bridge's base texture (frame 0)
    pa::MaterialDesc still;
    pa::MaterialDesc shown;
  };
  pa::MaterialDesc lookAt(const Entry& entry, double seconds) const;
  void show(Entry& entry, double seconds, pa::Renderer& renderer, bool force);

  std::vector<Entry> entries_;
  double seconds_ = 0.0;
  size_t lastUpdates_ = 0;
};

}  // namespace glue
