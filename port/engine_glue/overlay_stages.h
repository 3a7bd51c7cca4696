#pragma once
// 2D drawing of a scripted shader the way the stock renderer draws it: every stage in order,
// each with its own image (or animMap frame), blendFunc, alphaFunc, rgbGen/alphaGen colour and
// tcMod texture transform (menu backgrounds, logos, console, HUD effects). Colours and texture
// transforms are pure functions here; drawStages2D issues the GL calls.
#include <array>
#include <span>

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

/// A quad's four vertices inside glBegin(GL_QUADS) / glEnd.
void quadVertices(float x, float y, float w, float h, float s1, float t1, float s2, float t2);

/// One textured quad in window pixels with texture coordinates s1,t1 - s2,t2 (current GL state).
void drawQuad2D(float x, float y, float w, float h, float s1, float t1, float s2, float t2);

/// A DrawStretchPic rectangle held for a batch: window pixels, texture coordinates, and the
/// SetColor colour in force when it was drawn.
struct Quad2D {
  float x, y, w, h, s1, t1, s2, t2;
  Rgba color;
};

/// True when the stage draws an image in 2D (not a lightmap stage, not a video).
bool stageDraws2D(const q3::ShaderStage& stage);

/// Draws every 2D-drawable stage of a scripted shader (`look`) over the quads, stage by stage as
/// the stock renderer draws a batch of one shader: stage i with texture `stageTextures[i]`, each
/// quad in its own colour. The GL context must be current with the 2D projection.
void drawStages2D(const ShaderLook& look, std::span<const unsigned> stageTextures, double seconds,
                  std::span<const Quad2D> quads);

}  // namespace glue
