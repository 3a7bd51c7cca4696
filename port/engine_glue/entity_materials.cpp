// The still look of entity and effect shader stages as renderer materials (entity_materials.h).
#include "port/engine_glue/entity_materials.h"

#include "port/engine_glue/reflection_look.h"
#include "port/engine_glue/stock_look.h"

namespace glue {

bool unlitModelStage(const ShaderLook& look) {
  if (!look.fromScript) return false;   // an implicit model shader is rgbGen lightingDiffuse
  switch (look.rgbGen) {
    case q3::RgbGen::Default:
    case q3::RgbGen::Identity:
    case q3::RgbGen::IdentityLighting:
    case q3::RgbGen::Const: return true;
    default: return false;   // lit (lightingDiffuse, vertex), tinted by the entity, or waving
  }
}

bool lightColouredStage(const ShaderLook& look) {
  if (!look.fromScript) return true;   // an implicit model shader is rgbGen lightingDiffuse
  switch (look.rgbGen) {
    case q3::RgbGen::LightingDiffuse:
    case q3::RgbGen::Vertex:
    case q3::RgbGen::ExactVertex:
    case q3::RgbGen::OneMinusVertex: return true;
    default: return false;   // identity, const, wave, entity: the stage's own colour
  }
}

pa::MaterialDesc describeStage(const ShaderEntry& entry, const ShaderLook& look, const std::shared_ptr<const Image>& image,
                               MaterialUse use, uint32_t layer, const ImageTextures& texture) {
  pa::MaterialDesc desc;
  desc.baseTexture = texture(image, look.clamp, look.noPicmip);
  desc.stock.useVertexLight = use == MaterialUse::Model || use == MaterialUse::StockModel;
  // Effects (sprites, particles, marks) are unlit in every preset: composed over what is behind
  // them as the framebuffer composes them. Models in the traced presets are lit; there only the
  // additive family (dst GL_ONE) of their stages takes its source factor.
  const bool effect = use == MaterialUse::StockEffect || use == MaterialUse::Effect;
  const bool stockLayers = effect || use == MaterialUse::StockModel;
  // A lit model's stage whose colour does not come from the light (a muzzle flash's rgbGen
  // wave, a glow's identity or const) shows, in stock, what it blends by its own colour and alpha.
  const bool ownColourLayer = use == MaterialUse::Model && look.fromScript && !lightColouredStage(look);
  if (look.nodraw) desc.visible = false;
  if (look.fromScript) {
    const unsigned dst = look.blend.dst;
    const auto factors = layerFactors(look.blend);
    const bool plainAdd = look.blend.src == 1 && dst == 1;
    const bool factorLayer = stockLayers || dst == 1 || ownColourLayer;
    if (factorLayer && factors && look.blend.blends() && !plainAdd && !isAlphaBlend(look.blend) &&
        filterAsDarkening(look.blend) == Darkening::None) {
      // Any other blend of the layer's own colour and alpha (gl_one gl_src_alpha explosions,
      // gl_src_alpha gl_one glows), composed in display values as the framebuffer does: over
      // black, the traced presets add what the framebuffer would (the health sphere's pulsing
      // alpha, not its texture at full strength).
      desc.alphaMode = pa::AlphaMode::Additive;
      desc.stock.layerBlend = pa::LayerBlend::Factors;
      desc.stock.layerSrcFactor = factors->first;
      desc.stock.layerDstFactor = factors->second;
      desc.castsShadows = false;
      // The entity's colour reaches the stage only through rgbGen / alphaGen entity or vertex
      // (stock: a wave or identity colour comes with alpha 1).
      const bool entityRgb = look.vertexColor || look.rgbGen == q3::RgbGen::Entity;
      desc.vertexColorTints = entityRgb;
      // alphaGen lightingSpecular: the batch carries the stock specular alpha in the vertex
      // alpha of this layer's own vertex copies (specularAlphaLikeStock).
      desc.vertexAlphaTints = entityRgb || look.vertexAlpha || look.alphaGen == q3::AlphaGen::Entity ||
                              look.alphaGen == q3::AlphaGen::LightingSpecular;
    } else if (dst == 1 /*GL_ONE*/) {
      desc.alphaMode = pa::AlphaMode::Additive;
      desc.castsShadows = false;
    } else if (isAlphaBlend(look.blend) && stockLayers) {
      // Premultiplied over, in display values (the batch's vertex colours are premultiplied too:
      // premultiplyBlendedEffects), not the stochastic coverage that speckles at one sample.
      desc.baseTexture = texture(premultipliedImage(image), look.clamp, look.noPicmip);
      desc.alphaMode = pa::AlphaMode::Additive;
      desc.stock.layerBlend = pa::LayerBlend::Over;
      desc.stock.useVertexLight = false;   // a model's light is its vertex colour: it tints the layer
      desc.castsShadows = false;
    } else if (const auto darken = filterAsDarkening(look.blend); darken != Darkening::None && effect) {
      // dst * src (or dst * (1 - src): blob shadows) in display values, per channel.
      desc.alphaMode = pa::AlphaMode::Additive;
      desc.stock.layerBlend = darken == Darkening::BySourceColor ? pa::LayerBlend::Multiply : pa::LayerBlend::MultiplyInverse;
      desc.castsShadows = false;
    } else if (isAlphaBlend(look.blend)) {
      desc.alphaMode = pa::AlphaMode::Blend;
      desc.castsShadows = false;
    } else if (const auto darken = filterAsDarkening(look.blend); darken != Darkening::None) {
      // Multiplicative filters (bullet marks, blob shadows) darken what is behind. The tracer
      // has no multiply mode: draw them as black with an alpha of how much they darken.
      desc.baseTexture = texture(darkeningImage(image, darken), look.clamp, look.noPicmip);
      desc.alphaMode = pa::AlphaMode::Blend;
      desc.castsShadows = false;
    } else if (look.blend.blends()) {
      desc.visible = false;   // other exotic blends: not drawn
      desc.castsShadows = false;
    }
    if (look.alphaTest != AlphaTest::None && desc.alphaMode == pa::AlphaMode::Opaque) {
      desc.alphaMode = pa::AlphaMode::Mask;
      desc.alphaCutoff = look.alphaTest == AlphaTest::Gt0 ? 1.0f / 255.0f : 0.5f;
      desc.alphaInvert = look.alphaTest == AlphaTest::Lt128;
    }
  }
  if (look.rgbGen == q3::RgbGen::Const) {
    // rgbGen const: the stage's colour, whatever the blend (orange muzzle flashes).
    desc.baseColor = glm::vec4(byteToLinear(look.constColor[0] * 255.0f), byteToLinear(look.constColor[1] * 255.0f),
                               byteToLinear(look.constColor[2] * 255.0f), 1.0f);
  }
  if (entry.isDefault) desc.baseColor = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
  applyReflectionLook(look, desc);
  if (layer == 0 && entry.shineImage) applyShineLook(look, texture(entry.shineImage, look.shine->clamp, false), desc);
  if (use == MaterialUse::Model && !entry.isDefault && unlitModelStage(look) &&
      (desc.alphaMode == pa::AlphaMode::Opaque || desc.alphaMode == pa::AlphaMode::Mask) && desc.visible && !desc.mirror) {
    // The stock renderer draws such a stage at its texture's own colour whatever light falls on
    // it (the health items' chrome crosses): camera rays see that colour, and the surface
    // reflects nothing and lights nothing (no emitter to sample).
    desc.emissiveTexture = desc.baseTexture;
    desc.emissiveOwnUv = false;   // read where the base is read (its environment-mapped uvs too)
    desc.seenEmission = glm::vec3(desc.baseColor);
    desc.emission = glm::vec3(0.0f);
    desc.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, desc.baseColor.a);
    desc.specular = 0.0f;
  }
  return desc;
}

}  // namespace glue
