#include "port/engine_glue/overlay_stages.h"

#include <GL/gl.h>

#include <algorithm>

#include "port/engine_glue/shaders.h"

namespace glue {
namespace {

float clamp01(float v) { return std::clamp(v, 0.0f, 1.0f); }

}  // namespace

Rgba stageColor2D(const q3::ShaderStage& stage, const Rgba& setColor, double seconds) {
  using q3::RgbGen;
  Rgba c{1, 1, 1, 1};
  switch (stage.rgbGen) {
    case RgbGen::Default:            // identity or identityLighting: 1 in a window
    case RgbGen::Identity:
    case RgbGen::IdentityLighting:
    case RgbGen::LightingDiffuse:    // no light in 2D: the stock entity2D has none either; keep the image
      break;
    case RgbGen::Vertex:
    case RgbGen::ExactVertex:
    case RgbGen::Entity:             // a 2D quad's entity colour is the SetColor colour
      c = setColor;
      break;
    case RgbGen::OneMinusVertex:
    case RgbGen::OneMinusEntity:
      c = {1 - setColor[0], 1 - setColor[1], 1 - setColor[2], setColor[3]};
      break;
    case RgbGen::Wave: {
      const float glow = clamp01(stage.rgbWave.evaluate(seconds));
      c = {glow, glow, glow, 1};
      break;
    }
    case RgbGen::Const:
      c = {stage.constColor[0], stage.constColor[1], stage.constColor[2], 1};
      break;
  }
  using q3::AlphaGen;
  switch (stage.alphaGen) {
    case AlphaGen::Default:
    case AlphaGen::Identity:
      // Stock keeps the colour source's alpha only for rgbGen identity (1) and vertex.
      if (stage.rgbGen != RgbGen::Vertex) c[3] = 1;
      break;
    case AlphaGen::Vertex:
    case AlphaGen::Entity:
      c[3] = setColor[3];
      break;
    case AlphaGen::OneMinusVertex:
    case AlphaGen::OneMinusEntity:
      c[3] = 1 - setColor[3];
      break;
    case AlphaGen::Wave:
      c[3] = clamp01(stage.alphaWave.evaluate(seconds));
      break;
    case AlphaGen::Const:
      c[3] = stage.constAlpha;
      break;
    case AlphaGen::LightingSpecular:   // needs a surface and a light: none in 2D
    case AlphaGen::Portal:
      c[3] = 1;
      break;
  }
  for (float& v : c) v = clamp01(v);
  return c;
}

q3::UvAffine stageUvTransform2D(const q3::ShaderStage& stage, double seconds) {
  return q3::uvTransformAt(stage.tcMods, seconds);
}

void quadVertices(float x, float y, float w, float h, float s1, float t1, float s2, float t2) {
  glTexCoord2f(s1, t1); glVertex2f(x, y);
  glTexCoord2f(s2, t1); glVertex2f(x + w, y);
  glTexCoord2f(s2, t2); glVertex2f(x + w, y + h);
  glTexCoord2f(s1, t2); glVertex2f(x, y + h);
}

void drawQuad2D(float x, float y, float w, float h, float s1, float t1, float s2, float t2) {
  glBegin(GL_QUADS);
  quadVertices(x, y, w, h, s1, t1, s2, t2);
  glEnd();
}

bool stageDraws2D(const q3::ShaderStage& stage) {
  return stage.source == q3::TextureSource::Image && !stage.textures.empty();
}

void drawStages2D(const ShaderLook& look, std::span<const unsigned> stageTextures, double seconds,
                  std::span<const Quad2D> quads) {
  const std::vector<q3::ShaderStage>& stages = look.stages;
  for (size_t i = 0; i < stages.size() && i < stageTextures.size(); ++i) {
    const q3::ShaderStage& stage = stages[i];
    if (!stageDraws2D(stage)) continue;
    glBindTexture(GL_TEXTURE_2D, stageTextures[i]);
    if (stage.blends()) {
      glEnable(GL_BLEND);
      glBlendFunc(glBlendFactor(stage.srcBlend), glBlendFactor(stage.dstBlend));
    } else {
      glDisable(GL_BLEND);
    }
    switch (stage.alphaTest) {
      case q3::AlphaTest::None: glDisable(GL_ALPHA_TEST); break;
      case q3::AlphaTest::Gt0: glEnable(GL_ALPHA_TEST); glAlphaFunc(GL_GREATER, 0.0f); break;
      case q3::AlphaTest::Lt128: glEnable(GL_ALPHA_TEST); glAlphaFunc(GL_LESS, 0.5f); break;
      case q3::AlphaTest::Ge128: glEnable(GL_ALPHA_TEST); glAlphaFunc(GL_GEQUAL, 0.5f); break;
    }
    const q3::UvAffine uv = stageUvTransform2D(stage, seconds);
    // s' = a s + b t + tx, t' = c s + d t + ty as a column-major GL texture matrix.
    const GLfloat matrix[16] = {uv.a, uv.c, 0, 0, uv.b, uv.d, 0, 0, 0, 0, 1, 0, uv.tx, uv.ty, 0, 1};
    glMatrixMode(GL_TEXTURE);
    glLoadMatrixf(matrix);
    glBegin(GL_QUADS);
    for (const Quad2D& q : quads) {
      const Rgba color = stageColor2D(stage, q.color, seconds);
      glColor4f(color[0], color[1], color[2], color[3]);
      quadVertices(q.x, q.y, q.w, q.h, q.s1, q.t1, q.s2, q.t2);
    }
    glEnd();
  }
  glMatrixMode(GL_TEXTURE);
  glLoadIdentity();
  glMatrixMode(GL_MODELVIEW);
  glDisable(GL_ALPHA_TEST);
}

}  // namespace glue
