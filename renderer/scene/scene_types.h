#pragma once
// Plain descriptions handed to pa::Renderer: meshes, instances, textures, materials,
// lights, sky, camera and render settings. No Quake knowledge.
//
// Units and conventions (what the implementation in renderer/scene/ does):
// - Radiance is linear RGB in W/(sr m^2) of "scene units"; lengths are in the caller's units.
// - Point/spot lights: intensity I = color * intensity in W/sr. InverseSquare: irradiance at
//   distance d facing the light is I / d^2 (cut to 0 beyond range when range > 0). Linear:
//   I * max(0, 1 - d / range) (needs range > 0). A diffuse surface of albedo a lit head-on
//   therefore reflects a / pi * I / d^2. Spot: smoothstep from cosOuterAngle (0) to
//   cosInnerAngle (1). radius > 0 samples a point on the sphere (soft shadows).
// - Directional: color * intensity is the irradiance on a surface facing the light; the light
//   travels along `direction` (arrives from -direction); angularRadius spreads it over a cone.
// - Emission: a surface emits emission * emissiveTexture(uv) as radiance, from its front face
//   only when twoSided = false (front = counter-clockwise winding p0, p1, p2 seen from the
//   front, i.e. the side cross(p1 - p0, p2 - p0) points to). One-sided surfaces are also culled
//   from behind for camera and bounce rays (not for shadow rays).
// - Vertex colours multiply the base colour, except with stock.useVertexLight where they are baked
//   light: used by the Lightmap integrator only, ignored by Direct/Path, and interpolated across
//   the triangle in display (sRGB-encoded) values, as a raster renderer's Gouraud shading does.
// - Blend surfaces are stochastic coverage: a ray stops on them with probability
//   alpha * opacity (hashed per ray and triangle), for camera, bounce and shadow rays alike.
// - Additive surfaces add their colour (base colour + emission) to camera rays and mirror
//   reflections only: they neither occlude, shadow nor light other surfaces.
// - Sky surfaces (sky = true) show the sky; they are transparent to shadow rays aimed at the
//   sun or sky and block the others.
// - Integrators: Lightmap = emission + base colour x (stock.lightmapTexture at lightmapUvs, or the
//   vertex colour with stock.useVertexLight, or 1 when neither: fullbright). Direct = emission +
//   one light sample per camera sample (lights picked by power) with MIS against one BSDF
//   sample, plus the sky's ambient terms (SkyDesc::ambientRadiance, minimumRadiance). Path =
//   the same at every vertex.
// - maxBounces counts diffuse/glossy scattering events: 0 = emission and sky only,
//   1 = direct lighting, N = paths of up to N scattering vertices. Mirror bounces are free
//   (capped at maxBounces + 8 in total).
// - Portals (setPortals): a ray that hits the front of a mirror material lying on a portal's
//   plane does not reflect: it leaves from transform * hit point along mat3(transform) * its
//   direction (Quake III's mirrors and portal cameras), unweighted, for every ray but shadow
//   rays and in every integrator (Lightmap too), as a free bounce like a mirror's. Off every portal plane, or from behind, a
//   mirror material stays a mirror.
// - radianceClamp caps each light contribution of a path (light samples and emitters reached
//   by bounces) at that maximum RGB component; what the camera sees directly is never clamped.
// - Sky cube map: face f looks from the centre along its axis (+X, -X, +Y, -Y, +Z, -Z); its
//   image top points to +Z (to +X for the two Z faces) and its image right is axis x top
//   (+X face: right = -Y; +Y face: right = +X; +Z face: right = +Y; -Z face: right = -Y).
//   The faces are multiplied by color * intensity (set color to 1 to see them as they are).
// - Textures sample with (0, 0) at the top-left texel corner.
// - Fog volumes (setFogVolumes): a ray segment running a length L inside a volume gets the
//   opacity a = sqrt(clamp(L / depthForOpaque - 1/64, 0, 1)) (Quake III's fog curve) and
//   carries (1 - a) * what is behind + a * color (an absorbing, glowing medium; several
//   volumes compose front to back). Every segment of every integrator is fogged: camera,
//   mirror and portal rays gain the glow; bounce rays after a diffuse or glossy scattering and
//   shadow rays only lose (1 - a): the glow lights nothing (it stands for haze the scene's lights
//   already lit). Lightmap integrator: the stock look. A camera ray measures L along the
//   camera's forward axis (eye-space depth), every other segment its true length; only the
//   volumes holding the segment's end fog it (stock fogs surfaces inside a fog brush, never the
//   sky); and the blend is done on display values (sRGB-encoded, behind clamped to 1).
#include <array>
#include <memory>
#include <cmath>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <glm/mat2x2.hpp>
#include <glm/mat3x2.hpp>
#include <glm/mat4x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace pa {

/// Ids handed out by the Renderer. kNoId means "none".
using MeshId = uint32_t;
using InstanceId = uint32_t;
using TextureId = uint32_t;
using MaterialId = uint32_t;
using LightId = uint32_t;
inline constexpr uint32_t kNoId = 0xffffffffu;

/// Thrown on invalid input (non-finite numbers, out-of-range ids, size mismatches).
class SceneError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Triangle mesh. positions/indices are required; every other array is optional
/// (empty) or has one entry per vertex (normals, uvs, lightmapUvs, colors) or per
/// triangle (materials; empty = every triangle uses the default material).
struct MeshDesc {
  std::span<const glm::vec3> positions;
  std::span<const uint32_t> indices;          ///< 3 per triangle.
  std::span<const glm::vec3> normals;         ///< Shading normals; empty = geometric.
  std::span<const glm::vec2> uvs;             ///< Base texture coordinates.
  std::span<const glm::vec2> lightmapUvs;     ///< Baked-light texture coordinates (lightmap preset).
  std::span<const glm::vec4> colors;          ///< Linear vertex colours, multiply the base colour.
  std::span<const MaterialId> materials;      ///< One per triangle; kNoId = default grey diffuse.
  bool dynamic = false;                       ///< Expect per-frame vertex updates (refit instead of rebuild).
};

/// A MeshDesc viewing the arrays of `geometry`: its positions and indices and, where it has
/// members of these names, its normals, uvs, lightmapUvs and colors; `materials` one per
/// triangle. The description views geometry's arrays: use it while they live (addMesh and
/// updateMesh copy them).
template <class Geometry>
MeshDesc meshDescOf(const Geometry& geometry, std::span<const MaterialId> materials = {}, bool dynamic = false) {
  MeshDesc mesh;
  mesh.positions = geometry.positions;
  mesh.indices = geometry.indices;
  if constexpr (requires { geometry.normals; }) mesh.normals = geometry.normals;
  if constexpr (requires { geometry.uvs; }) mesh.uvs = geometry.uvs;
  if constexpr (requires { geometry.lightmapUvs; }) mesh.lightmapUvs = geometry.lightmapUvs;
  if constexpr (requires { geometry.colors; }) mesh.colors = geometry.colors;
  mesh.materials = materials;
  mesh.dynamic = dynamic;
  return mesh;
}

/// Texture addressing outside [0,1].
enum class TextureWrap : uint8_t { Repeat, Clamp };

/// RGBA8 texture, row-major from the top row. Mipmaps are generated when mipmaps = true.
struct TextureDesc {
  uint32_t width = 0;
  uint32_t height = 0;
  std::span<const uint8_t> rgba8;   ///< width * height * 4 bytes.
  bool srgb = true;                 ///< Colour data in sRGB (false for lightmaps stored linear, data).
  TextureWrap wrap = TextureWrap::Repeat;
  bool mipmaps = true;
};

/// How a surface combines with what is behind it.
enum class AlphaMode : uint8_t {
  Opaque,    ///< Solid.
  Mask,      ///< Alpha test against alphaCutoff (fences, grates, foliage).
  Blend,     ///< Translucent: opacity * alpha of colour, rest passes through (glass, water).
  Additive,  ///< Adds its colour to what is behind; no occlusion (flames, glows, beams).
};

/// How the Lightmap integrator composes an Additive layer over the display value dst behind
/// it; src is the layer's colour (texture x baseColor x vertex colour x tint) encoded for display.
enum class LayerBlend : uint8_t {
  Add,           ///< dst + src (glows, flames, beams).
  Over,          ///< dst * (1 - alpha) + src: premultiplied alpha blending (smoke).
  Multiply,      ///< dst * src: filters (marks); adds nothing.
  MultiplyInverse,  ///< dst * (1 - src): blob shadows; adds nothing.
  MultiplyAdd,   ///< dst * (1 + src): the stock dynamic-light pass; adds nothing by itself.
  Modulate2x,    ///< dst * 2 src: a filter that darkens below 0.5 and brightens above (gl_dst_color gl_src_color).
  /// src * layerSrcFactor + dst * layerDstFactor (StockLook): any framebuffer blend whose
  /// factors read only the layer's own colour and alpha. Layers only (not a shineBlend).
  Factors,
};

/// A blend factor that reads only the layer's own colour (src, display value) and alpha (a).
enum class BlendFactor : uint8_t {
  Zero,              ///< 0
  One,               ///< 1
  SrcColor,          ///< src, per channel
  OneMinusSrcColor,  ///< 1 - src, per channel
  SrcAlpha,          ///< a
  OneMinusSrcAlpha,  ///< 1 - a
};

/// Where a material's base texture coordinates come from (uvTransform applies after either).
enum class TexCoordSource : uint8_t {
  Mesh,              ///< The mesh's uvs.
  /// A sphere map of the mirrored view direction, per hit, in the instance's object space (the
  /// mesh's own frame): with n the interpolated shading normal and v the direction from the hit
  /// toward the viewer (-ray direction), both mapped to object space and normalised,
  /// r = 2 dot(n, v) n - v and uv = (0.5 + 0.5 r.y, 0.5 - 0.5 r.z). A surface facing +X seen
  /// head-on reads (0.5, 0.5). Chrome / "environment-mapped" looks; see textures/reflection_uv.h.
  ReflectionSphere,
};

/// A per-vertex wobble of mesh texture coordinates (rippling water, lava): each vertex's uv, after
/// uvTransform, moves by linear * amplitude * (sin(2 pi (dot(p, axisU) + phase)),
/// sin(2 pi (dot(p, axisV) + phase))), p the vertex's object-space position; between vertices the
/// offset is interpolated like the uvs. amplitude 0 = none. Mesh uvs only.
struct UvWobble {
  float amplitude = 0.0f;
  float phase = 0.0f;               ///< Cycles.
  glm::vec3 axisU{0.0f};            ///< Cycles per unit along which the u offset varies.
  glm::vec3 axisV{0.0f};            ///< Cycles per unit along which the v offset varies.
  glm::mat2 linear{1.0f};           ///< Maps the (u, v) offset (the linear part of later transforms).

  bool operator==(const UvWobble&) const = default;
  /// The offset at object-space position p.
  glm::vec2 offsetAt(const glm::vec3& p) const {
    constexpr float kTwoPi = 6.28318530718f;
    const glm::vec2 wave(std::sin(kTwoPi * (glm::dot(p, axisU) + phase)), std::sin(kTwoPi * (glm::dot(p, axisV) + phase)));
    return linear * (amplitude * wave);
  }
};

/// What only the Lightmap compositor reads (lightmap_compositor.h): the stock renderer's baked
/// light, its blend of see-through layers and its shine stage. Direct and Path ignore it, but
/// for useVertexLight, which also stops the vertex colour from tinting the base, and
/// lightmapStageScale, which brightens their base colour.
struct StockLook {
  TextureId lightmapTexture = kNoId;    ///< Baked light for the lightmap preset (uses lightmapUvs).
  bool useVertexLight = false;          ///< Baked light is the vertex colour.
  /// Display-value multiplier of base colour x baked light, clamped at white: a display whose
  /// gamma ramp multiplies what was drawn (Quake's overbright bits: 2^bits), times 2 for a
  /// lightmap stage that doubles what it multiplies (GL_DST_COLOR GL_SRC_COLOR).
  float bakedLightScale = 1.0f;
  /// The lightmap stage's own part of bakedLightScale: 2 where it doubles what it multiplies, else
  /// 1. Direct and Path show such a surface as stock does, its base colour that much brighter in
  /// display values (clamped at white) under the light they find (RenderScene::baseColor).
  float lightmapStageScale = 1.0f;
  /// Additive materials: how the Lightmap compositor composes the layer over what is behind it, in
  /// display values as framebuffer blending does (the other integrators add the colour).
  LayerBlend layerBlend = LayerBlend::Add;
  BlendFactor layerSrcFactor = BlendFactor::One;    ///< LayerBlend::Factors: multiplier of the layer's colour.
  BlendFactor layerDstFactor = BlendFactor::One;    ///< LayerBlend::Factors: multiplier of what is behind.
  /// A shine over the base (kNoId = none): a second image stage (Quake III's environment-mapped
  /// chrome over a painted model) that the Lightmap compositor composes over the lit base in
  /// display values, as framebuffer blending does: src = encode(shineTexture(shine uv) x
  /// shineColor) (x encode(vertex colour) with shineVertexColor), x (1 - base alpha) with
  /// shineMaskedByBaseAlpha, then dst = clamp(shineBlend(dst, src)). Direct/Path ignore it (give
  /// the material a glossy lobe through `specular` instead).
  TextureId shineTexture = kNoId;
  glm::vec3 shineColor{1.0f};                ///< Linear multiplier of the shine texture.
  bool shineVertexColor = false;             ///< The shine is tinted by the vertex colour too (rgbGen lightingDiffuse).
  bool shineMaskedByBaseAlpha = false;       ///< A later stage redraws the base alpha-blended: shine x (1 - base alpha).
  TexCoordSource shineTexCoords = TexCoordSource::ReflectionSphere;   ///< uv of shineTexture.
  glm::mat3x2 shineUvTransform{1.0f};        ///< Affine uv' = M * (u, v, 1) of the shine.
  LayerBlend shineBlend = LayerBlend::Add;   ///< How the shine meets the base (Over uses the shine's alpha).
  /// The stock dynamic-light pass multiplies the lit surface (StockDynamicLight): opaque world
  /// and brush-model surfaces, not sky, fog, mirrors or SURF_NODLIGHT ones.
  bool takesDynamicLights = false;

  bool operator==(const StockLook&) const = default;
};

/// Material model limited to what a Quake III scene needs.
struct MaterialDesc {
  TextureId baseTexture = kNoId;        ///< Albedo (RGB) + alpha (A).
  glm::vec4 baseColor{1.0f};            ///< Multiplies the texture (linear RGB, alpha).
  AlphaMode alphaMode = AlphaMode::Opaque;
  float alphaCutoff = 0.5f;             ///< Mask: alpha < cutoff is a miss (invert via alphaInvert).
  bool alphaInvert = false;             ///< Mask: alpha >= cutoff is a miss (Quake's LT128).
  float opacity = 1.0f;                 ///< Blend: overall opacity multiplier.
  TextureId emissiveTexture = kNoId;    ///< Emission map (RGB, sRGB); kNoId = constant emission.
  glm::vec3 emission{0.0f};             ///< Linear radiance multiplier (W/sr/m^2 in scene units).
  /// What camera rays see of the emission until their first scattering (mirror and portal
  /// chains included), where the look of an emitter was authored apart from the light it gives:
  /// radiance multiplier of emissiveTexture. Negative = `emission`. Light sampling and rays
  /// after a scattering always use `emission`.
  glm::vec3 seenEmission{-1.0f};
  /// Additive: texels whose alpha fails the alpha test (alphaCutoff, alphaInvert, as Mask tests
  /// coverage) add nothing and keep what is behind (Quake's alphaFunc on a blended stage).
  bool layerAlphaTest = false;
  bool vertexColorTints = true;         ///< The vertex colour's RGB multiplies the base (unless stock.useVertexLight).
  bool vertexAlphaTints = true;         ///< The vertex colour's alpha multiplies the base's alpha.
  bool mirror = false;                  ///< Perfect specular reflection (mirrors, portals seen as mirrors).
  float specular = 0.0f;                ///< Weight of a glossy lobe on top of diffuse (shiny env-mapped stages).
  /// The glossy lobe reflects in the base colour, not white: a stock shine stage that multiplies
  /// what lies under it (blendFunc GL_DST_COLOR ...) reflects tinted by the surface.
  bool specularTinted = false;
  float roughness = 0.3f;               ///< Roughness of that glossy lobe (GGX alpha = roughness^2).
  bool twoSided = true;                 ///< Quake surfaces are usually drawn from both sides (cull none).
  bool castsShadows = true;             ///< False: invisible to shadow rays.
  bool visible = true;                  ///< False: invisible to camera and bounce rays (nodraw, but may emit).
  bool sky = false;                     ///< Surface is a window to the sky: shows and emits the sky.
  glm::mat3x2 uvTransform{1.0f};        ///< Affine uv' = M * (u, v, 1): texture animation (scroll, rotate, scale).
  UvWobble uvWobble;                    ///< Per-vertex wobble added after uvTransform (mesh uvs).
  /// False: emissiveTexture is read at the base's uvs (after uvTransform and uvWobble). True: at
  /// the mesh uvs through emissiveUvTransform (a glow layer that moves on its own).
  bool emissiveOwnUv = false;
  glm::mat3x2 emissiveUvTransform{1.0f};  ///< Affine uv' = M * (u, v, 1) of emissiveTexture when emissiveOwnUv.
  TexCoordSource baseTexCoords = TexCoordSource::Mesh;   ///< uv of baseTexture (emissiveTexture keeps mesh uvs).
  /// An image covering the base by its alpha, under any light (kNoId = none): a stock stage
  /// blended over the base before the lightmap lights both (a launch pad's frame over its
  /// scrolling treads, terrain's second texture faded in by vertex alpha). The base colour's RGB
  /// becomes mix(base, cover, a), a the cover texture's alpha (x the vertex alpha with
  /// coverVertexAlpha; 0 below coverAlphaCutoff), the cover read at the mesh uvs through
  /// coverUvTransform; the Lightmap compositor mixes display values, as a framebuffer blends.
  /// The base's own alpha (coverage) is kept.
  TextureId coverTexture = kNoId;
  glm::mat3x2 coverUvTransform{1.0f};   ///< Affine uv' = M * (u, v, 1) of coverTexture.
  bool coverVertexAlpha = false;        ///< The cover's alpha is multiplied by the vertex colour's alpha.
  float coverAlphaCutoff = 0.0f;        ///< A cover alpha below it covers nothing (0: every alpha covers).
  StockLook stock;                      ///< Baked light, layer blend and shine of the Lightmap preset.

  bool operator==(const MaterialDesc&) const = default;
};

/// Instance visibility masks (bitwise OR).
enum InstanceMask : uint32_t {
  kMaskCamera = 1u << 0,   ///< Seen by primary rays.
  kMaskShadow = 1u << 1,   ///< Seen by shadow rays (casts shadows).
  kMaskBounce = 1u << 2,   ///< Seen by secondary (bounce, reflection) rays.
  kMaskAll = kMaskCamera | kMaskShadow | kMaskBounce,
};

/// One placed copy of a mesh. materialOverride, when set, replaces every triangle's material
/// (Quake's customShader); tint multiplies the base colour (shaderRGBA).
struct InstanceDesc {
  MeshId mesh = kNoId;
  glm::mat4x3 objectToWorld{1.0f};
  uint32_t mask = kMaskAll;
  MaterialId materialOverride = kNoId;
  glm::vec4 tint{1.0f};
  bool drawOnTop = false;   ///< Composited over the world regardless of depth (first-person weapon).

  bool operator==(const InstanceDesc&) const = default;
};

/// An instance drawn on top that only camera rays see (the first-person weapon): it changes no
/// other ray, so a moving one restarts accumulation only in the pixels it covers.
inline bool cameraOnlyOverlay(const InstanceDesc& instance) {
  return instance.drawOnTop && (instance.mask & ~uint32_t(kMaskCamera)) == 0;
}

/// Light source kinds. Emissive triangles are not lights here: they are collected from
/// materials with non-zero emission at commit() and sampled by power.
enum class LightType : uint8_t { Point, Spot, Directional };

/// Distance falloff of point and spot lights.
enum class Falloff : uint8_t {
  InverseSquare,  ///< Physical 1/d^2.
  Linear,         ///< max(0, 1 - d / range): Quake's "linear" lights and dynamic lights.
};

/// Analytic light. Point/spot: intensity in W/sr (colour * intensity); directional:
/// irradiance along -direction with an optional angular radius (soft sun).
struct LightDesc {
  LightType type = LightType::Point;
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};   ///< Spot axis / direction the sun light travels.
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  float radius = 0.0f;                      ///< Sphere radius for soft shadows (0 = point).
  Falloff falloff = Falloff::InverseSquare;
  float range = 0.0f;                       ///< Linear falloff range; also a cut-off when > 0.
  float cosInnerAngle = 1.0f;               ///< Spot: full intensity inside.
  float cosOuterAngle = 0.0f;               ///< Spot: zero outside.
  float angularRadius = 0.0f;               ///< Directional: half-angle of the sun disc, radians.

  bool operator==(const LightDesc&) const = default;
};

/// A sky picture computed per direction (e.g. cloud layers scrolled to one frame's time),
/// evaluated from any render thread: no state may change while a scene holds it.
class SkyPicture {
 public:
  virtual ~SkyPicture() = default;
  /// Linear radiance seen along a non-zero direction (world axes, Z up), before color * intensity.
  virtual glm::vec3 radiance(const glm::vec3& dir) const = 0;
};

/// Environment seen by rays that leave the scene (and through sky surfaces).
/// Faces order: +X, -X, +Y, -Y, +Z, -Z (world axes); all kNoId = constant colour.
struct SkyDesc {
  glm::vec3 color{0.0f};                    ///< Constant radiance, or multiplier of the cube map.
  std::array<TextureId, 6> faces{kNoId, kNoId, kNoId, kNoId, kNoId, kNoId};
  /// When set, what camera, mirror and bounce rays see instead of the faces (times color *
  /// intensity); the faces still give the sky's mean and its sampling distribution. Lets a
  /// moving sky change per frame without baking and re-uploading textures.
  std::shared_ptr<const SkyPicture> picture;
  float intensity = 1.0f;
  /// Extra multiplier where the sky lights surfaces (light samples, rays after a diffuse or
  /// glossy bounce); what the camera and mirrors see stays color * intensity. Lets a dark
  /// cube map light a scene as brightly as its author intended. 0 = the sky lights nothing.
  float lightingScale = 1.0f;
  /// Ambient light the scene's author asked for on every surface, unshadowed (Quake III
  /// worldspawn `_ambient`): radiance arriving from every direction that no occluder stops. At
  /// each diffuse or glossy path vertex of Direct and Path a surface of diffuse albedo a reflects
  /// a x ambientRadiance more (see lights/ambient.h); Lightmap ignores it (the bake holds it).
  glm::vec3 ambientRadiance{0.0f};
  /// The author's floor (worldspawn `_minlight`): at the same vertices the radiance reflected from
  /// that vertex's light sample plus the ambient term is raised, per channel, to at least
  /// a x minimumRadiance. Applied per sample, so under noisy light it converges to between the
  /// floor of the mean and the floor added (see lights/ambient.h).
  glm::vec3 minimumRadiance{0.0f};
};

/// A portal: the plane of a window (mirror-material surfaces on it) and where rays that enter it
/// come out. transform maps a point on the plane, and (its 3x3 part) a direction, to the other
/// side: a reflection about the plane for a mirror, a frame change for a portal camera.
struct PortalDesc {
  glm::vec3 normal{0.0f, 0.0f, 1.0f};   ///< Unit plane normal, pointing to the side it is seen from.
  float distance = 0.0f;               ///< Plane: dot(normal, p) = distance.
  glm::mat4x3 transform{1.0f};         ///< Affine map from this side to the far side (invertible).

  bool operator==(const PortalDesc&) const = default;
};

/// A fog volume: a convex region (inside where dot(plane.xyz, p) <= plane.w for every plane,
/// normals pointing out) of fog of a colour and a depth to opaque (see the conventions above).
struct FogVolumeDesc {
  std::span<const glm::vec4> planes;   ///< Bounding planes: xyz outward normal (any length), w distance.
  glm::vec3 color{0.5f};               ///< Linear radiance of the fog where it is opaque.
  float depthForOpaque = 1.0f;         ///< Length inside after which the fog is opaque (scene units, > 0).
};

/// A dynamic light as the stock renderer's lightmap look draws it (lights/stock_dlights.h): the
/// Lightmap compositor multiplies each surface that takes dynamic lights (StockLook) by one
/// plus a falloff blob projected along the world's z axis. Direct and Path ignore them (they
/// light with point lights, LightDesc).
struct StockDynamicLight {
  glm::vec3 origin{0.0f};
  float radius = 0.0f;        ///< Reach in world units (the engine's intensity); > 0 to light.
  glm::vec3 color{1.0f};      ///< In [0, 1] (clamped), display values.

  bool operator==(const StockDynamicLight&) const = default;
};

/// A game-style camera: origin and three axes (forward, left, up), field of view in degrees.
struct Camera {
  glm::vec3 origin{0.0f};
  glm::vec3 forward{1.0f, 0.0f, 0.0f};
  glm::vec3 left{0.0f, 1.0f, 0.0f};
  glm::vec3 up{0.0f, 0.0f, 1.0f};
  float fovX = 90.0f;
  float fovY = 73.74f;
};

/// Field of view (radians) across the other image axis: fovX from fovY with ratio = width/height,
/// fovY from fovX with ratio = height/width.
inline float fovAcross(float fovRadians, float ratio) {
  return 2.0f * std::atan(std::tan(0.5f * fovRadians) * ratio);
}

/// What the integrator computes per pixel.
enum class Integrator : uint8_t {
  Lightmap,  ///< Primary rays: base colour x baked light (lightmap or vertex colour); the original look.
  Direct,    ///< Direct light from every light with ray-traced shadows, plus emission.
  Path,      ///< Full path tracing: NEE + MIS, Russian roulette, maxBounces.
};

/// Display transform applied after exposure, before sRGB encoding.
enum class Tonemap : uint8_t {
  AcesFitted,   ///< Narkowicz 2015 fit of the ACES filmic curve, per channel.
  Reinhard,     ///< L / (1 + L) on luminance, hue preserved.
  Clamp,        ///< No curve, clamp to [0, 1] (the stock renderer's look).
};

/// How the reflected (lit) part of each pixel is shown, before exposure and tonemap.
enum class LightingLook : uint8_t {
  Physical,      ///< Radiance as traced.
  /// The look of engines that multiply a texture by a light map in 8-bit display values, the
  /// light clamped to 1 (scaled down as a whole, hue kept), and that add glow stages and additive
  /// effects in display values too: with E = (radiance - emission) / albedo per channel, the
  /// pixel shows linear(min(1, sRGB(albedo) x min(E, 1) + sRGB(emission))). A white Lambertian
  /// surface at radiance 1 is unchanged; dimmer light darkens as a light map does.
  DisplaySpace,
};

/// How a lookup uses the mip chain, as a raster texture unit's minification modes do.
enum class MipFilter : uint8_t {
  Linear,    ///< The two levels around the level of detail, blended (GL_*_MIPMAP_LINEAR).
  Nearest,   ///< The level nearest the level of detail (GL_*_MIPMAP_NEAREST).
  None,      ///< Level 0 only (GL_NEAREST, GL_LINEAR).
};

/// A texture unit's filtering (OpenGL's texture modes, a stock renderer's r_textureMode).
struct TextureFilter {
  MipFilter mips = MipFilter::Linear;
  bool nearestTexels = false;   ///< The texel the point falls in (GL_NEAREST*); else bilinear.
  bool operator==(const TextureFilter&) const = default;
};

/// Per-render knobs. The image is a pure function of (scene, camera, seed, frameIndex, spp),
/// independent of the thread count.
struct RenderSettings {
  uint32_t width = 640;
  uint32_t height = 360;
  Integrator integrator = Integrator::Path;
  uint32_t samplesPerPixel = 1;   ///< Per render() call.
  /// Every camera ray goes through its pixel's centre (no jitter): the sampling of a raster
  /// renderer, so that a one-sample frame shows each texture as a rasteriser shows it and does
  /// not change with the seed; with taau, through the centre moved by TAAU's jitter, the same
  /// for every pixel of a frame (where the upscaler expects the samples).
  bool pixelCentres = false;
  /// How the Lightmap integrator's surfaces filter their base and shine textures, as a stock
  /// renderer's texture units do (its r_textureMode). Lightmaps are read bilinearly, as stock does.
  TextureFilter stockTextureFilter{};
  uint32_t maxBounces = 4;
  /// Direct and Path: a path whose last vertex (after maxBounces scatterings) lies on a surface
  /// with baked light (StockLook: lightmap or vertex light) takes the bake's light there
  /// (integrator/baked_light.h) instead of ending dark: the bounced light the map compiler
  /// traced, for no extra ray. False: paths end after their last light sample (unbiased for
  /// the scene's lights).
  bool bakedLightAtPathEnd = false;
  float radianceClamp = 0.0f;     ///< Clamp on each path's contribution; 0 = off (reference).
  /// Direct and Path: scattering events after which Russian roulette may end a path, each
  /// further ray traced with probability max(throughput) and its light divided by it (unbiased,
  /// noisier). 1 applies it to the first bounce ray already: a bounce off a dark surface is
  /// seldom traced. Never less than 1.
  uint32_t rouletteStart = 3;
  uint32_t seed = 0;
  bool accumulate = true;         ///< Average with earlier frames while camera and scene are unchanged.
  /// With accumulate, for a still view of a world that keeps moving (play): a scene edit restarts
  /// only the pixels that show it (an instance, material or the sky, this frame or the last) and
  /// whose first hit is now another surface (instance, material, or depth off by over 5%), and
  /// lighting edits are averaged over the frames as in a long exposure; a texture, fog or
  /// removed-mesh edit still restarts every pixel. False: any edit restarts every pixel.
  bool accumulateThroughEdits = false;
  float exposure = 1.0f;          ///< Linear multiplier before tonemapping.
  Tonemap tonemap = Tonemap::AcesFitted;   ///< Display transform (does not reset accumulation).
  /// How the lit part is shown; DisplaySpace also has Direct and Path sum what the camera sees of
  /// emitters, sky and additive stages in display values (PixelSample::emission), so a change
  /// restarts accumulation.
  LightingLook lightingLook = LightingLook::Physical;
  /// Edge-aware à-trous filter of the mean (renderer/scene/denoise) before exposure and tonemap:
  /// the returned radiance and rgba8 are filtered, the accumulation is not (does not reset it).
  bool denoise = false;
  /// With denoise or temporal: after temporal accumulation and before the denoiser, cut each
  /// pixel whose lit radiance is far above its neighbourhood's and share the excess among its
  /// neighbours on the same surface (renderer/scene/denoise/fireflies.h): the frame keeps its
  /// energy. Does not reset accumulation.
  bool spreadFireflies = false;
  /// Trace camera rays 4x4 pixels at a time (BVH packet queries): the same image, faster; false
  /// traces them one by one (for A/B measurements). Does not reset accumulation.
  bool cameraPackets = true;
  /// Temporal accumulation (renderer/scene/temporal, SVGF's temporal stage) of Direct and Path
  /// frames rendered without `accumulate`: each frame blends with the last ones, reprojected by
  /// the camera's and the instances' motion, before the denoiser. Ignored by Lightmap and while
  /// accumulating. Its history starts again when size, integrator, spp, bounces or clamp change.
  bool temporal = false;
  /// With `temporal`: temporal gradients (renderer/scene/temporal/gradients.h, after A-SVGF):
  /// per gradientStratum x gradientStratum pixels one of last frame's samples is traced again in
  /// this frame's scene with its own random numbers, and where the lighting changed the history
  /// is dropped in proportion. Not with `restir` (its first samples cannot be retraced alone).
  bool temporalGradients = true;
  /// Side of the pixel blocks that get one retraced sample each (2..16; GradientConfig::stratum):
  /// 6 costs one sample in 36. A change starts the gradients again (one frame without).
  uint32_t gradientStratum = 6;
  /// Direct light at each pixel's first diffuse or glossy hit by spatiotemporal reservoir
  /// resampling (renderer/scene/restir, ReSTIR DI) instead of one light sample: many light
  /// samples weighed per pixel, last frame's and neighbours' reused. Direct and Path only; its
  /// history starts again when the image size changes. Unbiased for a still scene (README there).
  bool restir = false;
  /// Temporal anti-aliasing and upscaling (renderer/scene/taau) of the encoded frame to
  /// outputWidth x outputHeight (FrameView::output): with pixelCentres, each frame's camera rays
  /// move by a sub-pixel Halton jitter, and a history at the output size gathers the samples.
  /// Does not reset accumulation; its history starts again when the output size changes.
  bool taau = false;
  uint32_t outputWidth = 0;    ///< TAAU's output width; 0 = width.
  uint32_t outputHeight = 0;   ///< TAAU's output height; 0 = height.
  /// Fill FrameView::motion. False: a frame whose motion nothing in the renderer reads (no
  /// temporal stage, no TAAU) leaves it out and hands FrameView::motion out empty; the instance
  /// and material ids are written either way. Does not reset accumulation.
  bool motionVectors = true;
  /// Fill FrameView::normal with the shading normal. False: a Lightmap frame without the
  /// denoiser (nothing else there reads normals) skips interpolating it and holds the winding
  /// normal there instead; the picture is the same. Does not reset accumulation.
  bool normalAov = true;
  /// Fill FrameView::albedo and FrameView::normal. False: a frame of one sample per pixel that
  /// nothing filters (no accumulate, denoise or temporal stage) with the Physical lighting look
  /// writes only radiance, depth and variance per pixel and hands those two out empty; the next
  /// frame that accumulates starts again rather than resume from it. Other frames fill them
  /// anyway. Does not reset accumulation.
  bool surfaceAovs = true;
};

}  // namespace pa
