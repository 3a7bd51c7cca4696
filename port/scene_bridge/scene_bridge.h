#pragma once
// pa::bridge: puts a q3::WorldScene into pa::Renderer's flat scene API.
//
// Units: Quake units stay scene units (1 unit ~ 1 inch), Z up. Analytic light intensities come
// converted by the world builder (port/q3formats/world/world_lights.h): a q3map2 light value of
// 64 (what the lightmap shows as "full bright") becomes irradiance pi, so a white Lambertian
// surface reaches radiance 1 (white at exposure 1) in the Direct and Path integrators exactly
// where the Lightmap integrator shows the texture unmodified.
// Lightmaps are uploaded with Quake's overbright shift (x4, hue-preserving clamp, the look of
// r_overBrightBits 0) and as sRGB data, because Quake multiplies texture and lightmap in gamma
// space and lin(a) * lin(b) ~= lin(a * b) for a power-law transfer.
#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "port/q3formats/world/world_scene.h"
#include "renderer/scene/renderer.h"

namespace pa::bridge {

/// How far world surfaces of a shader with polygonOffset (map decals) move along their normal,
/// in map units: decals often lie in the plane of the wall they mark, where rounding would decide
/// pixel by pixel which of the two a camera ray meets first; stock draws them over it with its
/// depth offset. 0.1 unit is far beyond that rounding and too little to see.
inline constexpr float kWorldDecalLift = 0.1f;

/// Knobs of uploadWorld.
struct UploadOptions {
  /// Add the map's analytic lights (scene.lights: light entities, q3map_sun, and the lights
  /// port/light_recovery recovered when the caller put them there).
  bool lights = true;
  float lightScale = 1.0f;   ///< Multiplies every light intensity and emission (artistic exposure).
  float skyIntensity = 1.0f; ///< Radiance multiplier of the sky.
  /// Lightmaps are brightened by 2^lightmapShift with hue-keeping saturation (Quake's
  /// r_mapOverBrightBits minus the display's overbright bits; 2 by default), except images a
  /// shader stage names (WorldScene::lightmapNamedByShader), which stock draws unbrightened.
  int lightmapShift = 2;
  /// StockLook::bakedLightScale of the world's lightmapped and vertex-lit materials (the
  /// display's overbright: 2^bits when a gamma ramp doubles what was drawn).
  float bakedLightScale = 1.0f;
};

/// A map's fog volumes in the renderer's terms, owning the plane arrays the descriptions view.
struct FogVolumes {
  FogVolumes() = default;
  FogVolumes(FogVolumes&&) = default;
  FogVolumes& operator=(FogVolumes&&) = default;
  FogVolumes(const FogVolumes&) = delete;   ///< A copy would view the original's planes.
  std::vector<std::vector<glm::vec4>> planes;   ///< One array per volume.
  std::vector<FogVolumeDesc> volumes;           ///< planes[i] viewed by volumes[i].
};

/// Renderer ids of everything uploaded, indexed like the WorldScene arrays.
struct WorldHandles {
  std::vector<TextureId> textures;          ///< Per WorldScene::textures (kNoId when empty).
  std::vector<TextureId> lightmaps;         ///< Per WorldScene::lightmaps.
  std::map<std::pair<uint32_t, int32_t>, MaterialId> materials;   ///< (material, lightmap) -> id.
  std::map<uint32_t, MaterialId> lightProxies;   ///< Material -> invisible emitter (additive surface lights).
  std::vector<MeshId> modelMeshes;          ///< Per WorldScene::models: one mesh (kNoId when empty).
  std::vector<InstanceId> modelInstances;   ///< Per model: identity instance (kNoId when empty).
  std::vector<LightId> lights;              ///< Per light added (scene.lights with a positive, finite intensity).
  uint64_t triangles = 0;
  float bakedLightScale = 1.0f;   ///< UploadOptions::bakedLightScale, for materialDesc.
  /// The map's sky (skyDesc()) and fog volumes (fogVolumes()) with the upload's options: the
  /// caller shows them (showSkyAndFog) or replaces them with its own.
  SkyDesc sky;
  FogVolumes fog;
};

/// The fog brushes of a map: the brush planes, the fogParms colour (a display colour, made
/// linear, times lightScale) and depthForOpaque raised to at least 1 unit as the stock renderer
/// does. Fogs whose brush has no usable plane are left out.
FogVolumes fogVolumes(const q3::WorldScene& scene, float lightScale = 1.0f);

/// The renderer light of a scene light, its intensity times lightScale.
LightDesc lightDesc(const q3::WorldLight& light, float lightScale = 1.0f);

/// Uploads textures, lightmaps, materials, one mesh + instance per model and lights, and
/// returns their ids with the sky and fog volumes it made (WorldHandles::sky, fog; not set on
/// the renderer). Does not commit(). Brush sub-model instances start at identity; movers set
/// their transform.
WorldHandles uploadWorld(const q3::WorldScene& scene, Renderer& renderer, const UploadOptions& options = {});

/// Sets the sky and fog volumes of an upload on the renderer (which copies them).
void showSkyAndFog(const WorldHandles& handles, Renderer& renderer);

/// The sky: the box faces (or the average colour) as they look, lighting the map as q3map2
/// did: SkyDesc::lightingScale brings the box's mean to the radiance of the sky shader's
/// q3map_skylight, or to 0 when the shader lit the map by q3map_sun alone. Other boxes keep
/// their look as their light; a box-less sky shows and lights with the radiance of its
/// q3map_surfacelight + q3map_skylight. Carries the worldspawn's `_ambient` / `_minlight`
/// (WorldScene::ambientLight, minimumLight) as ambientRadiance / minimumRadiance, light value / 64
/// times lightScale.
SkyDesc skyDesc(const q3::WorldScene& scene, const WorldHandles& handles, const UploadOptions& options = {});

/// Radiance (RGB) with which skyDesc()'s sky lights surfaces (its lighting, not its look):
/// the mean of the box faces or the constant colour, times intensity and lightingScale.
glm::vec3 skyLightingRadiance(const q3::WorldScene& scene, const UploadOptions& options = {});

/// The renderer material for one world material drawn with one lightmap (-1 = none).
MaterialDesc materialDesc(const q3::WorldScene& scene, const WorldHandles& handles, uint32_t material, int32_t lightmap,
                          float lightScale = 1.0f);

/// The invisible light-only twin of an additive q3map_surfacelight material (flames): the
/// renderer never samples additive surfaces as lights, q3map2 does. nullopt for other materials.
std::optional<MaterialDesc> surfaceLightProxy(const q3::WorldScene& scene, const WorldHandles& handles,
                                              uint32_t material, float lightScale = 1.0f);

/// Quake's lightmap brightening: value * 2^shift per channel, scaled down as a whole when one
/// channel would pass 255 (hue kept). RGBA8 in, RGBA8 out.
std::vector<uint8_t> colorShiftLightmap(const std::vector<uint8_t>& rgba8, int shift);

/// A renderer camera at a spawn point; fovX in degrees over an image of the given aspect (w/h).
Camera cameraFromSpawn(const q3::WorldCamera& spawn, float aspect, float fovX = 90.0f);

}  // namespace pa::bridge
