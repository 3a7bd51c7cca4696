#pragma once
// Lightmap preset helpers that make traced views look like the stock opengl1 renderer's
// picture: model vertex colours, blended effects, extra shader layers and the world's unlit
// surfaces (used by views_traced.cpp; each function says which stock behaviour it follows).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <unordered_map>

#include <glm/mat4x3.hpp>
#include <glm/vec3.hpp>

#include "port/engine_glue/entity_geometry.h"
#include "port/engine_glue/entity_lighting.h"
#include "port/engine_glue/images.h"
#include "port/engine_glue/ioq3_abi.h"
#include "port/engine_glue/settings.h"
#include "port/engine_glue/shaders.h"
#include "port/q3formats/world/world_scene.h"
#include "renderer/scene/scene_types.h"

namespace q3 {
class ShaderLibrary;
}

namespace glue {

/// An 8-bit gamma-space value (0..255) as linear light, the sRGB transfer undone.
float byteToLinear(float byte);

/// True for the stock alpha blend (GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA).
bool isAlphaBlend(const BlendFunc& blend);

/// RGBA with the colour multiplied by alpha (alpha kept).
std::shared_ptr<const Image> premultipliedImage(const std::shared_ptr<const Image>& image);

/// The renderer's blend factors of a stage's blend when both read only the stage's own colour and
/// alpha (ZERO, ONE, SRC_COLOR, ONE_MINUS_SRC_COLOR, SRC_ALPHA, ONE_MINUS_SRC_ALPHA); nullopt
/// for blends that read the framebuffer in their source factor (DST_COLOR ...).
std::optional<std::pair<pa::BlendFactor, pa::BlendFactor>> layerFactors(const BlendFunc& blend);

/// How a multiplicative blend darkens: by the source colour, or by its inverse.
enum class Darkening : uint8_t { None, BySourceColor, ByInverseSourceColor };

/// The darkening a stage's blend function makes (None for any other blend).
Darkening filterAsDarkening(const BlendFunc& blend);

/// Black RGBA whose alpha is how much `image` darkens what is behind it.
std::shared_ptr<const Image> darkeningImage(const std::shared_ptr<const Image>& image, Darkening mode);

/// Vertex colours of alpha-blended effect triangles premultiplied by their alpha, linearised
/// (the lightmap preset composes such effects as premultiplied-over layers in display values:
/// encode(lin(c) * lin(a)) ~ c * a).
void premultiplyBlendedEffects(ShaderRegistry& shaders, GeometryBatch& batch);

/// Each vertex of an MD3 batch gets the colour the stock renderer gives it: grid light per
/// vertex normal (rgbGen lightingDiffuse, implicit model shaders), entity colour or white.
/// Stock multiplies texture and colour bytes in gamma space; the tracer multiplies linear
/// values, so the bytes are linearised (lin(a) * lin(b) ~ lin(a * b)).
void lightModelLikeStock(const q3abi::refEntity_t& e, const glm::mat4x3& toWorld, const EntityLight& light,
                         ShaderRegistry& shaders, GeometryBatch& batch);

/// Repeats the triangles of shaders that have extra additive layers once per layer
/// (batch.triangleLayers tells which layer each triangle draws).
void addShaderLayers(ShaderRegistry& shaders, GeometryBatch& batch);

/// The alpha byte stock opengl1 gives a vertex for `alphaGen lightingSpecular` (tr_shade_calc.c):
/// a fixed light at (-960, 1980, 96) in the model's own space, its direction mirrored about the
/// vertex normal, dotted with the unit direction to the viewer (object space), to the 4th power,
/// x 255, truncated; 0 when the dot is negative.
uint8_t stockSpecularAlpha(const glm::vec3& position, const glm::vec3& normal, const glm::vec3& viewer);

/// Lightmap preset, after addShaderLayers: the triangles of every (shader, layer) for which
/// `specular` is true (a stage with alphaGen lightingSpecular) get copies of their vertices whose
/// alpha is stockSpecularAlpha / 255 seen from `viewer` (object space); the other layers keep the
/// vertices they share.
void specularAlphaLikeStock(const std::function<bool(q3abi::qhandle_t shader, uint32_t layer)>& specular,
                            const glm::vec3& viewer, GeometryBatch& batch);

/// World surfaces whose shader has no lightmap stage and no vertex-colour stage (q3::deriveMaterial
/// says Unlit) are drawn by opengl1 at full texture brightness (rgbGen identityLighting): their
/// vertex colours become white (the lightmap preset multiplies them in; the traced presets ignore
/// vertex colours of vertex-lit surfaces); the vertex colours of vertex-lit surfaces get the
/// stock overbright shift (x4, hue kept). Also records each material's glow colour (rgbGen const
/// of its first additive stage, linear), which the stock look adds.
/// r_picmip and r_intensity on the world's textures, as stock treats mipmapped images: every
/// texture but those of nopicmip / nomipmaps shaders and the sky is halved picmip times; every
/// texture's colours are multiplied by the intensity.
void applyPictureToWorld(q3::WorldScene& scene, const q3::ShaderLibrary& library, const PictureSettings& picture);

/// `lightShift` replaces the x4 (kLightOverbrightShift; r_mapOverBrightBits minus display bits).
void stockWorldLook(q3::WorldScene& scene, const q3::ShaderLibrary& library,
                    std::unordered_map<uint32_t, glm::vec3>& glowColors, int lightShift = kLightOverbrightShift);

}  // namespace glue
