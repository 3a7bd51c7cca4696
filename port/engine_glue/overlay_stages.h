#pragma once
// 2D drawing of a scripted shader the way the stock renderer draws it: every stage in order,
// each with its own image (or animMap frame), blendFunc, alphaFunc, rgbGen/alphaGen colour and
// tcMod texture transform (menu backgrounds, logos, console, HUD effects). Colours and texture
// transforms are pure functions here; drawStages2D issues the GL calls.
#include <array>

#include "port/engine_glue/ioq3_abi.h"
#include "port/engine_glue/shaders.h"
#include "port/q3formats/shader/material.h"
#include "port/q3formats/shader/shader_types.h"

namespace glue {

class Engine;
class ShaderRegistry;

/// RGBA in [0, 1].
using Rgba = std::array<float, 4>;

/// A stage's vertex colour in 2D: rgbGen then alphaGen, from the SetColor colour (the quad's
/// vertex colour) at time `seconds`, with the stock rules (identityLight = 1 in a window:
/// the stock renderer turns overbright bits off without hardware gamma or fullscreen).
Rgba stageColor2D(const q3::ShaderStage& stage, const Rgba& setColor, double seconds);

/// The stage's texture-coordinate map at `seconds` (its tcMods; turb and entityTranslate,
/// which need per-vertex or entity data, are left out).
q3::UvAffine stageUvTransform2D(const q3::ShaderStage& stage, double seconds);

/// One textured quad in window pixels with texture coordinates s1,t1 - s2,t2 (current GL state).
void drawQuad2D(float x, float y, float w, float h, float s1, float t1, float s2, float t2);

/// True when the stage draws an image in 2D (not a lightmap stage, not a video).
bool stageDraws2D(const q3::ShaderStage& stage);

/// Draws every 2D-drawable stage of `shader`'s script over the rectangle (window pixels,
/// texture coordinates s1,t1 - s2,t2). The GL context must be current with the 2D projection.
/// `images` reads a stage's images on its first draw.
void drawStages2D(ShaderRegistry& shaders, const Engine& engine, const ImageSource& images, q3abi::qhandle_t shader,
                  double seconds, const Rgba& setColor, float x, float y, float w, float h, float s1, float t1,
                  float s2, float t2);

}  // namespace glue
