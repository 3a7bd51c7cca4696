#pragma once
// Renderer materials of entity and effect shader stages: how each stage's blend, alpha test and
// colour generator maps onto a pa::MaterialDesc (the still look; shader_animation.h moves it).
#include <cstdint>
#include <functional>
#include <memory>

#include "port/engine_glue/images.h"
#include "port/engine_glue/shaders.h"
#include "renderer/scene/scene_types.h"

namespace glue {

/// Kinds of materials made from one shader. StockEffect: an effect in the lightmap preset, where
/// alpha-blended effects (smoke puffs) are premultiplied-over layers (src * a + dst * (1 - a)) and
/// filters (marks, blob shadows) multiply layers (dst * src, dst * (1 - src)), composed in display
/// values like the stock blend stages (the tracer's stochastic blend would speckle at one sample
/// per pixel). StockModel: a model in the lightmap preset, whose stages that blend by their own
/// colour and alpha (gl_src_alpha gl_one health spheres) are such display-value layers too.
enum class MaterialUse : uint8_t { Model, Effect, StockEffect, StockModel };

/// The renderer texture of an image (repeating or clamped to its edges, picmip applied unless
/// noPicmip), made on first use.
using ImageTextures = std::function<pa::TextureId(const std::shared_ptr<const Image>& image, bool clamp, bool noPicmip)>;

/// True for a model stage the stock renderer draws at its texture's colour whatever the light
/// (a scripted stage whose rgbGen is identity, identityLighting, const or left out); the traced
/// presets show it so, as an unlit surface.
bool unlitModelStage(const ShaderLook& look);

/// True for a model stage whose colour comes from the light or the vertices (rgbGen
/// lightingDiffuse, vertex; an implicit shader); false for its own colour (identity, const, wave,
/// entity), which the traced presets compose as a layer when it blends by that colour and alpha.
bool lightColouredStage(const ShaderLook& look);

/// The still look (no animation) of stage `layer` (0 = the shader's first) of a shader drawn as
/// `use` with `image`.
pa::MaterialDesc describeStage(const ShaderEntry& entry, const ShaderLook& look, const std::shared_ptr<const Image>& image,
                               MaterialUse use, uint32_t layer, const ImageTextures& texture);

}  // namespace glue
