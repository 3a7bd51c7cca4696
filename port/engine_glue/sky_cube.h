#pragma once
// The stock sky as a cube map for the tracer's environment (pa::SkyDesc): opengl1 draws a sky
// shader's far box (skyParms <farbox>) and then its stages as cloud layers, each mapped onto a
// dome of radius 4096 raised by the cloud height (ioquake3 tr_sky.c R_InitSkyTexCoords,
// FillCloudBox; the bottom face gets no clouds). We bake the same picture per direction into six
// faces in pa's face order (+X, -X, +Y, -Y, +Z, -Z) and orientation, at a given shader time so
// that scrolling clouds move as in the stock renderer.
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "port/engine_glue/images.h"
#include "port/q3formats/shader/material.h"   // q3::UvAffine
#include "port/q3formats/shader/shader_types.h"
#include "renderer/scene/scene_types.h"   // pa::SkyPicture

namespace glue {

/// Loads a game image by path (any extension), nullptr when it cannot be read.
using SkyImageLoader = std::function<std::shared_ptr<const Image>(const std::string& path)>;

/// World direction (not normalised) through texel centre (x, y) of cube face `face` (0..5) with
/// `size` texels a side, in pa's cube convention (renderer/scene/lights/sky.cpp cubeLookup).
glm::vec3 skyCubeDirection(int face, int x, int y, int size);

/// The stock cloud-layer texture coordinates (before tcMods) of a world direction (Z up):
/// the ray from the eye meets a sphere of radius 4096 + cloudHeight centred 4096 units below
/// the eye; s and t are the arc cosines of that point's unit x and y.
glm::vec2 cloudTexCoords(const glm::vec3& direction, float cloudHeight);

/// Six RGBA8 faces of `size` x `size` texels.
struct SkyCube {
  int size = 0;
  std::array<std::vector<uint8_t>, 6> faces;
};

/// Mean linear colour of a cube's six sRGB faces (each face weighted alike, as the bridge
/// weighs a far box's faces).
glm::vec3 skyCubeMeanLinear(const SkyCube& cube);

/// The traced presets' sky: what rays see is `stock` (the stock look), what lights surfaces is
/// the bridge's: lightingScale brings the brightest channel of `stockMean` (skyCubeMeanLinear of
/// the stock faces) to that of `lighting` (pa::bridge::skyLightingRadiance: what the compiler lit
/// the map with through the sky; 0 lights nothing), and the ambient light and floor are `bridge`'s.
/// A black stock look that should light gives `bridge` itself.
pa::SkyDesc litStockSky(const pa::SkyDesc& stock, const glm::vec3& stockMean, const pa::SkyDesc& bridge,
                        const glm::vec3& lighting);

/// Bakes a sky shader's stock look.
class SkyBaker {
 public:
  /// Reads the shader's far box and cloud stage images. False (and nothing to bake) when the
  /// shader has neither a far box nor an image stage.
  bool prepare(const q3::ShaderDef& shader, const SkyImageLoader& load, int size);
  /// True when the clouds move with time (a stage has tcMods or wave colours).
  bool animated() const { return animated_; }
  /// Writes the six faces at shader time `seconds`, rows in parallel (tbb::parallel_for: call it
  /// inside the task arena whose threads it may use).
  void bake(double seconds, SkyCube& out) const;

  /// The cloud layers' uv transforms and colours at one shader time.
  struct LayerState {
    std::vector<q3::UvAffine> transforms;
    std::vector<glm::vec4> colors;
  };
  /// The layers' state at shader time `seconds`.
  LayerState layersAt(double seconds) const;
  /// The same, written into `state` (its vectors keep their memory).
  void layersAt(double seconds, LayerState& state) const;
  /// The display colour (each channel in [0, 1]) seen along a non-zero direction: the far box
  /// and the cloud layers in `state`; what bake() writes at a texel centre, without its resampling.
  glm::vec3 colorAt(const glm::vec3& direction, const LayerState& state) const;

 private:
  /// `color` under the cloud layers at cloud coordinates `st`.
  glm::vec3 composeClouds(glm::vec3 color, glm::vec2 st, const LayerState& state) const;

  struct Layer {
    q3::ShaderStage stage;
    std::shared_ptr<const Image> image;
  };
  std::array<std::shared_ptr<const Image>, 6> farBox_;   ///< Cube order (q3::SkyBox): rt lf bk ft up dn.
  std::vector<Layer> layers_;
  int size_ = 0;
  std::vector<glm::vec2> cloudCoords_;   ///< Per texel of faces 0..4 (the bottom has no clouds).
  std::vector<glm::vec3> boxColors_;     ///< Far-box colour per texel of the six faces (time-free).
  float cloudHeight_ = 0.0f;
  bool animated_ = false;
};

/// The stock sky of a prepared baker at one shader time, per direction: display colour decoded
/// to linear radiance, for pa::SkyDesc::picture (what camera rays see; no texture is baked or
/// uploaded). Moved to another time in place (setTime), without allocating, while no render reads it.
class StockSkyPicture final : public pa::SkyPicture {
 public:
  StockSkyPicture(std::shared_ptr<const SkyBaker> baker, double seconds);
  glm::vec3 radiance(const glm::vec3& dir) const override;
  /// The clouds at shader time `seconds`.
  void setTime(double seconds);

 private:
  std::shared_ptr<const SkyBaker> baker_;
  SkyBaker::LayerState state_;
};

/// A StockSkyPicture of a prepared baker at shader time `seconds`. Null for null.
std::shared_ptr<StockSkyPicture> stockSkyPictureAt(std::shared_ptr<const SkyBaker> baker, double seconds);

}  // namespace glue
