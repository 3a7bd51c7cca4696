#pragma once
// glTF data -> the renderer's plain descriptions (pure functions, no pa::Renderer needed).
//
// Mapping (documented here once):
//  - glTF texture (image + sampler) -> one sRGB RGBA8 texture with mipmaps, Repeat or Clamp.
//  - Material: baseColorFactor x baseColorTexture, alphaMode/alphaCutoff, emissiveFactor x
//    KHR_materials_emissive_strength (x emissiveTexture) as emitted radiance, doubleSided ->
//    twoSided, metallic/roughness -> a glossy lobe of weight 0.04 + 0.96 * metallic (dielectric
//    Fresnel at normal incidence .. full metal) with the file's roughness.
//    Material `extras` flags (true/1/"true"): "sky" (window to the sky), "mirror", "nodraw"
//    (invisible, may still emit), "noshadows", "additive" (AlphaMode::Additive), "alphaInvert";
//    assets_converter's "quake.sky", "quake.mirror" and "quake.blend": "add" are honoured too.
//  - Lightmaps (primitive extras "lightmapTexture" + TEXCOORD_n, as assets_converter writes them):
//    one material variant per (material, lightmap); lightmap pixels are brightened by the scene's
//    "quake.lightmapOverbrightScale" with per-texel saturation that keeps the hue (as Quake does at
//    load) and uploaded as sRGB, so that linear(texture) x linear(lightmap) shows like the stock
//    renderer's texture x lightmap product.
//  - Lights (KHR_lights_punctual): point/spot intensity in candela and directional illuminance
//    in lux are used as W/sr and W/m^2 after LoadOptions::lightUnitScale (default 1), the same
//    factor that scales emissive strength, so lights and emitters stay balanced;
//    range > 0 -> cut-off. Spot cone angles -> cosines.
//  - Sky: scene `extras` "sky_color" (or "quake.sky.color"; [r, g, b], linear) and
//    "sky_intensity"; default black.
#include <cstdint>
#include <span>
#include <vector>

#include "renderer/gltf_io/gltf_scene.h"
#include "renderer/scene/scene_types.h"

namespace pa::gltf {

/// The MaterialDesc that a glTF material becomes (textures: renderer ids per glTF texture).
MaterialDesc toMaterialDesc(const GltfMaterial& material, const std::vector<TextureId>& textures);

/// The LightDesc that a glTF light becomes.
LightDesc toLightDesc(const GltfLight& light);

/// A material's lightmap stage factor (StockLook::lightmapStageScale) from its extras
/// ("quake.lightmapStageScale", in (0, 4]; default 1).
float lightmapStageScale(const GltfMaterial& material);

/// Brightness factor for lightmap pixels from the scene's extras (default 1).
float lightmapBrightness(const Extras& sceneExtras);

/// Lightmap RGBA8 pixels times `scale`, saturated per texel keeping the hue; alpha 255.
std::vector<uint8_t> brightenLightmap(std::span<const uint8_t> rgba8, float scale);

/// The sky described by the scene's extras ("sky_color", "sky_intensity"); black if absent.
SkyDesc toSkyDesc(const Extras& sceneExtras);

/// A renderer camera from a glTF camera for an image of the given aspect (width / height):
/// the vertical field of view is kept, the horizontal one follows the image.
Camera toCamera(const GltfCamera& camera, float imageAspect);

}  // namespace pa::gltf
