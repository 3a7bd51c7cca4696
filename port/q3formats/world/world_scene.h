#pragma once
// q3::WorldScene: a Quake III map as a plain scene description (meshes grouped by material
// per model, materials, textures, lightmaps, lights, sky, cameras, fog volumes, light grid).
// Built once from a parsed BSP and the shader scripts; consumed by the engine glue (through
// pa_scene_bridge) and by assets_converter (glTF). Coordinates stay in Quake units (Z-up,
// 1 unit ~ 1 inch); converting units/axes is the consumer's business.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "port/q3formats/bsp/tessellate.h"
#include "port/q3formats/shader/shader_types.h"

namespace q3 {

struct BspFile;       // port/q3formats/bsp: the parsed IBSP 46 file
class ShaderLibrary;  // port/q3formats/shader: every shader script of the game

/// Fetches a game file's bytes by its game path ("textures/base_wall/foo.tga");
/// std::nullopt when the file does not exist. Lets the engine (ri.FS_ReadFile) and the
/// converter (GameFileSystem over .pk3 archives) feed the same builder.
using FileLoader = std::function<std::optional<std::vector<std::byte>>(std::string_view path)>;

/// Axis-aligned box in Quake units. Empty when mins > maxs.
struct WorldBounds {
  glm::vec3 mins{3.0e38f};
  glm::vec3 maxs{-3.0e38f};
  /// Grows the box to contain p.
  void extend(const glm::vec3& p);
  /// True when nothing was added.
  bool empty() const { return mins.x > maxs.x; }
};

/// A decoded RGBA8 image, row-major from the top row.
struct WorldImage {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> rgba8;   ///< width * height * 4 bytes.
};

/// A texture used by materials or the sky, decoded once and shared by index.
struct WorldTexture {
  std::string requestedPath;   ///< Path named by the shader (extension as written, may be absent).
  std::string resolvedPath;    ///< File actually read (".tga" -> ".jpg" fallback applied); empty = fallback image.
  WorldImage image;            ///< Decoded pixels (the fallback checker when the file is missing/broken).
  bool clamp = false;          ///< clampmap: no repeat outside [0,1].
  bool isFallback = false;     ///< True when the file was missing or undecodable.
};

/// How a surface combines with what is behind it (mirrors pa::AlphaMode, glTF alphaMode).
enum class WorldAlphaMode : uint8_t {
  Opaque,    ///< Solid.
  Mask,      ///< alphaFunc GT0 / GE128 / LT128: alpha test.
  Blend,     ///< blendFunc blend (src alpha, 1 - src alpha): translucent.
  Additive,  ///< blendFunc add / (one, one) and friends: adds light, occludes nothing.
  Filter,    ///< blendFunc filter and friends: multiplies what is behind (filterBlend), occludes nothing.
};

/// True for the modes that occlude nothing (Additive, Filter): see-through layers over what is
/// behind them, which cast no shadow and are no surface light of their own.
inline bool seeThroughLayer(WorldAlphaMode mode) {
  return mode == WorldAlphaMode::Additive || mode == WorldAlphaMode::Filter;
}

/// A material: one Quake shader as the renderers need it.
struct WorldMaterial {
  std::string shaderName;        ///< Name in the BSP shader lump (no extension).
  int32_t surfaceFlags = 0;      ///< SURF_* bits (BSP shader lump, OR-ed with the script's surfaceparms).
  int32_t contentFlags = 0;      ///< CONTENTS_* bits.
  bool fromScript = false;       ///< False: implicit shader (image of the same name, lightmapped).

  int32_t baseTexture = -1;      ///< Index into WorldScene::textures (-1 = none: white).
  glm::vec4 baseColor{1.0f};     ///< Linear RGBA multiplier of the base texture (rgbGen/alphaGen const).
  WorldAlphaMode alphaMode = WorldAlphaMode::Opaque;
  float alphaCutoff = 0.5f;      ///< Mask (and additiveAlphaTest): GT0 -> 1/255, GE128/LT128 -> 0.5.
  bool alphaInvert = false;      ///< Mask (and additiveAlphaTest): LT128 (alpha < 0.5 is kept).
  /// Additive: the first stage's source factor (destination GL_ONE): One adds the texture,
  /// SrcAlpha the texture x its alpha, DstColor multiplies what is behind by 1 + the texture.
  BlendFactor additiveSource = BlendFactor::One;
  bool additiveAlphaTest = false;  ///< Additive with alphaFunc: texels failing the test add nothing.
  FilterBlend filterBlend = FilterBlend::Multiply;  ///< Filter: how it multiplies what is behind.
  float opacity = 1.0f;          ///< Blend: overall opacity.

  glm::vec3 emission{0.0f};      ///< Linear emitted colour in [0,1] (q3map_lightImage/average texture colour).
  float surfaceLight = 0.0f;     ///< q3map_surfacelight value as authored (0 = not emissive).
  int32_t emissiveTexture = -1;  ///< Texture that glows (additive glow stage or the base), -1 = constant.

  bool twoSided = true;          ///< cull none/twosided (Quake default is back-face culled: false).
  bool visible = true;           ///< False for nodraw / hint / skip surfaces (kept only when they emit).
  bool castsShadows = true;      ///< False for sky, trans-only additive, nodraw.
  bool sky = false;              ///< surfaceparm sky: a window to the sky box.
  bool fog = false;              ///< surfaceparm fog: the boundary of a fog volume.
  bool decal = false;            ///< polygonOffset: drawn over the surface it lies on.
  bool mirror = false;           ///< portal / mirror surface.
  bool vertexLit = false;        ///< Baked light comes from vertex colours (no lightmap stage).
  float specular = 0.0f;         ///< Env-mapped (tcGen environment) stage strength in [0,1].
  glm::vec2 uvScrollPerSecond{0.0f};  ///< tcMod scroll of the base stage (texture units / s).
  glm::vec2 uvScale{1.0f};       ///< tcMod scale of the base stage.
  std::vector<TcMod> tcMods;     ///< The base stage's tcMods in script order (uvScale and uvScrollPerSecond summarise them).
  bool baseReflects = false;     ///< Base stage is tcGen environment: a sphere map read at the mirrored view.
  int32_t reflectionOverlayTexture = -1;  ///< baseReflects: the surface's own texture added over the reflection (-1 = none).
  /// Texture blended over the base by its alpha before the lightmap lights both (a launch pad's
  /// frame over its scrolling treads, terrain's second texture by vertex alpha), -1 = none.
  int32_t coverTexture = -1;
  std::vector<TcMod> coverTcMods;  ///< The cover's tcMods, on the mesh uvs.
  bool coverVertexAlpha = false;   ///< The cover's alpha is multiplied by the vertex alpha.
  float coverAlphaCutoff = 0.0f;   ///< Cover alpha below it covers nothing (alphaFunc GE128: 0.5).
  /// Multiplier of the lit colour by the shader's lightmap stage (2: GL_DST_COLOR GL_SRC_COLOR).
  float lightmapScale = 1.0f;
  int32_t lightmap = -1;         ///< Lightmap the shader names itself (q3map2's external lm_NNNN stage), index
                                 ///< into WorldScene::lightmaps; -1 = the surface's lightmap number decides.
};

/// A triangle mesh with one material (and one lightmap), in Quake units.
struct WorldMesh {
  uint32_t material = 0;         ///< Index into WorldScene::materials.
  int32_t lightmap = -1;         ///< Index into WorldScene::lightmaps, -1 = vertex-lit or unlit.
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;      ///< Unit length, one per vertex.
  std::vector<glm::vec2> uvs;          ///< Base texture coordinates (Quake st).
  std::vector<glm::vec2> lightmapUvs;  ///< Lightmap coordinates in [0,1] of that lightmap.
  std::vector<glm::vec4> colors;       ///< Vertex colours as stored (bytes / 255; baked light of vertex-lit surfaces).
  std::vector<uint32_t> indices;       ///< 3 per triangle, counter-clockwise seen from the front.
  WorldBounds bounds;
  uint32_t sourceSurfaces = 0;         ///< BSP surfaces merged into this mesh.
};

/// Model 0 is the world; models 1..N are brush sub-models ("*1".."*N": doors, platforms).
struct WorldModel {
  std::vector<WorldMesh> meshes;   ///< One per (material, lightmap) pair.
  WorldBounds bounds;              ///< From the BSP model lump.
};

/// Kind of an analytic light.
enum class WorldLightType : uint8_t { Point, Spot, Sun };

/// A light from a `light` entity or a q3map_sun. Quake semantics kept beside the
/// converted physical ones (see world_lights.h for the conversion).
struct WorldLight {
  WorldLightType type = WorldLightType::Point;
  glm::vec3 position{0.0f};      ///< Point/spot origin (Quake units).
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  ///< Spot axis, or the direction sunlight travels.
  glm::vec3 color{1.0f};         ///< `_color`, normalised so the largest channel is 1.
  float quakeIntensity = 300.0f; ///< `light` key as authored (q3map2 default 300); sun: q3map_sun intensity.
  bool linearFalloff = false;    ///< spawnflags & 1 (q3map2 "linear" light).
  float intensity = 0.0f;        ///< Converted: W/sr for point/spot, irradiance for the sun (renderer units).
  float range = 0.0f;            ///< Linear lights: distance at which the light reaches zero; 0 = unbounded.
  float cosOuterAngle = 0.0f;    ///< Spot: cosine of the cone half-angle (target + `radius` key).
  float cosInnerAngle = 1.0f;    ///< Spot: full intensity inside.
  float angularRadius = 0.0f;    ///< Sun: half-angle of the disc (radians).
  std::string source;            ///< "entity 12 (light)", "q3map_sun in textures/skies/x".
  /// Recovered from the light grid or the lightmaps (not authored), by port/light_recovery.
  bool estimated = false;
  /// Estimated lights: the largest value the lightmaps allow (a lightmap candidate must not give
  /// the texel it was read from more light than the texel shows); the calibration fits below it.
  float maxQuakeIntensity = std::numeric_limits<float>::infinity();
};

/// The environment: a sky box (six images) or a constant colour.
struct WorldSky {
  std::string shaderName;                 ///< The sky shader used by the map ("" = none).
  /// Faces in world order +X, -X, +Y, -Y, +Z, -Z (q3::SkyBox layout: Quake suffixes rt, lf, bk,
  /// ft, up turned 180 degrees, dn); indices into WorldScene::textures, -1 = absent (then use colour).
  std::array<int32_t, 6> faces{-1, -1, -1, -1, -1, -1};
  glm::vec3 color{0.0f};                  ///< Average colour of the box (or of the sky texture).
  float cloudHeight = 0.0f;               ///< skyParms cloud height (data only).
  float surfaceLight = 0.0f;              ///< q3map_surfacelight of the sky shader (q3map2 sky light), 0 = none.
  float skyLight = 0.0f;                  ///< q3map_skylight value (q3map2's dome of suns), 0 = none.
  int skyLightIterations = 0;             ///< q3map_skylight iterations (q3map2 ignores fewer than 2).
  bool sunLit = false;                    ///< The sky shader has q3map_sun: the compiler lit the map by it.
};

/// A viewpoint: spawn points and the intermission camera.
struct WorldCamera {
  std::string name;              ///< Entity classname + index ("info_player_deathmatch 3").
  glm::vec3 eye{0.0f};           ///< Origin + (0, 0, 9 + 26): spawn lift plus the default view height.
  glm::vec3 forward{1.0f, 0.0f, 0.0f};
  glm::vec3 left{0.0f, 1.0f, 0.0f};
  glm::vec3 up{0.0f, 0.0f, 1.0f};
  float fovX = 90.0f;            ///< Degrees (cg_fov default).
};

/// A fog volume: the fog brush (a convex region) filled with the fog of its shader's fogParms.
struct WorldFog {
  std::string shaderName;
  WorldBounds bounds;            ///< Bounds of the fog brush.
  /// The brush's side planes, xyz unit outward normal and w distance (inside where
  /// dot(xyz, p) <= w); non-finite or zero-normal sides dropped. Empty when the brush has none usable.
  std::vector<glm::vec4> planes;
  glm::vec3 color{0.5f};         ///< fogParms colour.
  float depthForOpaque = 0.0f;   ///< fogParms distance to full opacity (Quake units).
};

/// The baked light grid (8 bytes per point), for LightForPoint-style lookups.
struct WorldLightGrid {
  glm::vec3 origin{0.0f};        ///< World position of sample (0, 0, 0).
  glm::vec3 cellSize{64.0f, 64.0f, 128.0f};
  std::array<int32_t, 3> counts{0, 0, 0};
  std::vector<std::array<uint8_t, 8>> samples;   ///< ambient RGB, directed RGB, longitude, latitude.
};

/// Everything the renderers and the converter need from one map.
struct WorldScene {
  std::string mapName;                   ///< "maps/oa_dm1.bsp" as given.
  std::vector<WorldModel> models;        ///< [0] world, [1..] brush sub-models.
  std::vector<WorldMaterial> materials;
  std::vector<WorldTexture> textures;
  /// Baked lightmaps: RGB(A=255) as stored, 128x128 from the lump, any size from external
  /// lm_NNNN images (world_external_lightmaps.h). Quake brightens them at load by
  /// 2^r_mapOverBrightBits (= 4, with per-texel saturation keeping hue): a stored value of
  /// 64 is "full bright". kLightmapOverbrightScale carries that factor.
  std::vector<WorldImage> lightmaps;
  /// Per lightmap (shorter vectors: false for the rest): true when a shader stage names the
  /// image (q3map2's lightmap shaders for sizes other than 128). The stock renderer draws those
  /// as ordinary images, without the brightening of lump pages.
  std::vector<bool> lightmapNamedByShader;
  std::vector<WorldLight> lights;
  WorldSky sky;
  std::vector<WorldCamera> cameras;
  std::vector<WorldFog> fogs;
  WorldLightGrid lightGrid;
  /// Worldspawn `_ambient` (else `ambient`) x `_color`, in q3map2 light values (64 = full bright):
  /// the compiler added it to every lightmap texel before any light.
  glm::vec3 ambientLight{0.0f};
  /// Worldspawn `_minlight` x `_color` (light values): the compiler's floor on every lightmap texel.
  glm::vec3 minimumLight{0.0f};
  std::vector<std::string> warnings;     ///< Content problems found (missing textures, bad keys, ...).
};

/// Stored lightmap value x this = light relative to "full bright" (Quake's map overbright shift).
inline constexpr float kLightmapOverbrightScale = 4.0f;

/// Knobs of the builder.
struct WorldBuildOptions {
  bool loadTextures = true;        ///< False: keep paths only (images left empty).
  bool keepInvisible = false;      ///< Keep nodraw/hint/skip surfaces that do not emit.
  int patchSubdivisions = 4;       ///< Patch error tolerance in Quake units (r_subdivisions).
};

/// How buildWorldScene tessellates the map's surfaces for `options` (patchSubdivisions).
inline TessellationOptions worldTessellation(const WorldBuildOptions& options = {}) {
  TessellationOptions tessellation;
  tessellation.maxError = float(options.patchSubdivisions);
  return tessellation;
}

/// Builds the scene of a parsed map. Throws FormatError only for a malformed BSP; content
/// problems (missing shader -> implicit shader, missing texture -> fallback) become warnings.
WorldScene buildWorldScene(const BspFile& bsp, const ShaderLibrary& shaders, const FileLoader& loadFile,
                           const WorldBuildOptions& options = {});

/// The same from the map's surfaces as tessellateSurfaces(bsp, worldTessellation(options))
/// made them, for a caller that keeps the tessellation for itself too (the engine module's
/// decals): the map is tessellated once.
WorldScene buildWorldScene(const BspFile& bsp, std::span<const SurfaceMesh> surfaces, const ShaderLibrary& shaders,
                           const FileLoader& loadFile, const WorldBuildOptions& options = {});

}  // namespace q3
