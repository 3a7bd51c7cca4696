#include "port/engine_glue/overlay2d.h"

#include <SDL.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <cstddef>
#include <cstdlib>

#include "port/engine_glue/overlay_stages.h"
#include "port/engine_glue/picture_upscale.h"
#include "port/engine_glue/shaders.h"

namespace glue {
namespace {

constexpr int kCinematicSlots = 16;   // the engine's MAX_VIDEO_HANDLES
constexpr int kMaxSlots = Overlay2D::kViewSlots + kCinematicSlots;

}  // namespace

void Overlay2D::beginFrame(int width, int height, bool fillsSurface) {
  flushPics();
  fillsSurface_ = fillsSurface;
  width_ = width;
  height_ = height;
  glViewport(0, 0, width, height);
  glScissor(0, 0, width, height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_LIGHTING);
  glEnable(GL_TEXTURE_2D);
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glOrtho(0, width, height, 0, -1, 1);
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
  glClearColor(0, 0, 0, 1);
  // On a software GL every cleared pixel costs CPU: the clear waits for the first draw, which
  // usually paints the whole window opaque (the traced world view).
  clipped_ = false;
  clearPending_ = true;
  color_ = {1, 1, 1, 1};
}

void Overlay2D::clearIfPending() const {
  if (!clearPending_) return;
  clearPending_ = false;
  if (clipped_) glDisable(GL_SCISSOR_TEST);
  glClear(GL_COLOR_BUFFER_BIT);
  if (clipped_) glEnable(GL_SCISSOR_TEST);
}

void Overlay2D::finishDrawing() {
  flushPics();
  clearIfPending();
}

void Overlay2D::applyRamp(const std::array<uint8_t, 256>& ramp) {
  if (width_ <= 0 || height_ <= 0) return;
  flushPics();
  clearIfPending();
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (prepareCopy(width_, height_)) {
    // Read in the window's byte order (no conversion), mapped into the copy with the rows
    // turned top-first, and copied back.
    glReadPixels(0, 0, width_, height_, GL_BGRA, GL_UNSIGNED_INT_8_8_8_8_REV, copyPixels_.data());
    const size_t row = size_t(width_) * 4;
    for (int y = 0; y < height_ / 2; ++y)
      std::swap_ranges(copyPixels_.begin() + ptrdiff_t(size_t(y) * row), copyPixels_.begin() + ptrdiff_t(size_t(y + 1) * row),
                       copyPixels_.begin() + ptrdiff_t(size_t(height_ - 1 - y) * row));
    for (size_t i = 0; i < copyPixels_.size(); i += 4)
      for (size_t c = 0; c < 3; ++c) copyPixels_[i + c] = ramp[copyPixels_[i + c]];
    if (clipped_) glDisable(GL_SCISSOR_TEST);
    blitCopy(0, 0);
    if (clipped_) glEnable(GL_SCISSOR_TEST);
    return;
  }
  rampPixels_.resize(size_t(width_) * size_t(height_) * 4);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rampPixels_.data());
  for (size_t i = 0; i < rampPixels_.size(); i += 4)
    for (size_t c = 0; c < 3; ++c) rampPixels_[i + c] = ramp[rampPixels_[i + c]];
  glPushAttrib(GL_ENABLE_BIT | GL_COLOR_BUFFER_BIT | GL_CURRENT_BIT | GL_PIXEL_MODE_BIT);
  glDisable(GL_TEXTURE_2D);
  glDisable(GL_BLEND);
  glDisable(GL_ALPHA_TEST);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_SCISSOR_TEST);
  glPixelZoom(1.0f, 1.0f);
  glMatrixMode(GL_PROJECTION);
  glPushMatrix();
  glLoadIdentity();
  glOrtho(0, width_, 0, height_, -1, 1);
  glMatrixMode(GL_MODELVIEW);
  glPushMatrix();
  glLoadIdentity();
  glRasterPos2i(0, 0);
  glDrawPixels(width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rampPixels_.data());
  glPopMatrix();
  glMatrixMode(GL_PROJECTION);
  glPopMatrix();
  glMatrixMode(GL_MODELVIEW);
  glPopAttrib();
}

void Overlay2D::clip(int x, int y, int w, int h) {
  flushPics();
  clipped_ = true;
  glEnable(GL_SCISSOR_TEST);
  glScissor(x, height_ - (y + h), std::max(0, w), std::max(0, h));
}

void Overlay2D::clearClip() {
  flushPics();
  clipped_ = false;
  glScissor(0, 0, width_, height_);
  glDisable(GL_SCISSOR_TEST);
}

void Overlay2D::setColor(const float* rgba) {
  if (rgba == nullptr) color_ = {1, 1, 1, 1};
  else color_ = {rgba[0], rgba[1], rgba[2], rgba[3]};
}

void Overlay2D::drawPic(ShaderRegistry& shaders, const Engine& engine, const ImageSource& images,
                        q3abi::qhandle_t shader, double seconds, float x, float y, float w, float h, float s1,
                        float t1, float s2, float t2) {
  const ShaderEntry& entry = shaders.resolve(shader);
  if (entry.look.nodraw) return;
  if (!batch_.quads.empty() && (batch_.shaders != &shaders || batch_.shader != shader || batch_.seconds != seconds))
    flushPics();
  clearIfPending();
  if (batch_.quads.empty()) {
    // The batch's textures: the same for each of its quads (one shader at one time).
    batch_.shaders = &shaders;
    batch_.shader = shader;
    batch_.seconds = seconds;
    const std::vector<q3::ShaderStage>& stages = entry.look.stages;
    batch_.stages = entry.look.fromScript && std::any_of(stages.begin(), stages.end(), stageDraws2D);
    batch_.textures.clear();
    if (batch_.stages) {
      for (size_t i = 0; i < stages.size(); ++i)
        batch_.textures.push_back(stageDraws2D(stages[i]) ? shaders.stageGlTexture(engine, images, shader, i, seconds) : 0u);
    } else {
      batch_.textures.push_back(shaders.glTexture(shader, seconds));
    }
  }
  batch_.quads.push_back({x, y, w, h, s1, t1, s2, t2, color_});
}

void Overlay2D::flushPics() const {
  if (batch_.quads.empty()) return;
  const ShaderLook& look = batch_.shaders->resolve(batch_.shader).look;
  if (batch_.stages) {
    drawStages2D(look, batch_.textures, batch_.seconds, batch_.quads);
    batch_.quads.clear();
    return;
  }
  glBindTexture(GL_TEXTURE_2D, batch_.textures.front());
  const BlendFunc blend = look.blend;
  if (blend.blends()) {
    glEnable(GL_BLEND);
    glBlendFunc(blend.src, blend.dst);
  } else {
    glDisable(GL_BLEND);
  }
  switch (look.alphaTest) {
    case AlphaTest::None: glDisable(GL_ALPHA_TEST); break;
    case AlphaTest::Gt0: glEnable(GL_ALPHA_TEST); glAlphaFunc(GL_GREATER, 0.0f); break;
    case AlphaTest::Lt128: glEnable(GL_ALPHA_TEST); glAlphaFunc(GL_LESS, 0.5f); break;
    case AlphaTest::Ge128: glEnable(GL_ALPHA_TEST); glAlphaFunc(GL_GEQUAL, 0.5f); break;
  }
  glBegin(GL_QUADS);
  for (const Quad2D& q : batch_.quads) {
    const float r = look.vertexColor ? q.color[0] : 1.0f;
    const float g = look.vertexColor ? q.color[1] : 1.0f;
    const float b = look.vertexColor ? q.color[2] : 1.0f;
    const float a = look.vertexAlpha || look.vertexColor ? q.color[3] : 1.0f;
    glColor4f(r, g, b, a);
    quadVertices(q.x, q.y, q.w, q.h, q.s1, q.t1, q.s2, q.t2);
  }
  glEnd();
  glDisable(GL_ALPHA_TEST);
  batch_.quads.clear();
}

unsigned Overlay2D::slotTexture(int slot) {
  if (slotTextures_.empty()) {
    slotTextures_.assign(kMaxSlots, 0);
    slotSizes_.assign(kMaxSlots, {0, 0});
  }
  if (slotTextures_[slot] == 0) {
    GLuint texture = 0;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    slotTextures_[slot] = texture;
  }
  return slotTextures_[slot];
}

void Overlay2D::upload(int slot, const uint8_t* rgba, int width, int height) {
  glBindTexture(GL_TEXTURE_2D, slotTexture(slot));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (slotSizes_[slot][0] != width || slotSizes_[slot][1] != height) {
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    slotSizes_[slot] = {width, height};
  } else {
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
  }
}

void Overlay2D::uploadRaw(int client, const uint8_t* rgba, int cols, int rows) {
  const int slot = kViewSlots + client;
  if (slot < kViewSlots || slot >= kMaxSlots || rgba == nullptr || cols <= 0 || rows <= 0) return;
  flushPics();
  upload(slot, rgba, cols, rows);
}

void Overlay2D::drawRaw(int client, float x, float y, float w, float h) {
  const int slot = kViewSlots + client;
  if (slot < kViewSlots || slot >= kMaxSlots || slotTextures_.empty() || slotTextures_[slot] == 0) return;
  flushPics();
  clearIfPending();
  glBindTexture(GL_TEXTURE_2D, slotTextures_[slot]);
  glDisable(GL_BLEND);
  drawTexelsQuad(x, y, w, h);
}

void Overlay2D::drawPixels(int slot, const uint8_t* rgba, int width, int height, float x, float y,
                           float w, float h, bool opaque) {
  if (rgba == nullptr || width <= 0 || height <= 0 || slot < 0 || slot >= kViewSlots) return;
  flushPics();
  // An opaque picture over the whole unclipped window replaces every pixel the clear would set
  // (the quad's edges are the viewport's, so it covers every pixel centre).
  if (opaque && fillsSurface_ && !clipped_ && x == 0.0f && y == 0.0f && w == static_cast<float>(width_) &&
      h == static_cast<float>(height_))
    clearPending_ = false;
  clearIfPending();
  if (opaque && copyPicture(rgba, width, height, x, y, w, h)) return;
  upload(slot, rgba, width, height);
  if (opaque) {
    glDisable(GL_BLEND);
  } else {
    // Premultiplied: where nothing was hit (alpha 0) the additive effects the ray crossed still
    // add their colour to what is behind, as stock additive stages do over the 2D menu.
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  }
  drawTexelsQuad(x, y, w, h);
}

void Overlay2D::prepareForPlay(int width, int height) {
  if (width_ <= 0 || height_ <= 0) return;
  // A see-through model view's draw, with nothing in it: premultiplied black of alpha 0 adds nothing.
  const uint8_t nothing[4] = {0, 0, 0, 0};
  drawPixels(1, nothing, 1, 1, 0.0f, 0.0f, 1.0f, 1.0f, false);
  if (width <= 0 || height <= 0) return;
  const bool copied = (width == width_ && height == height_) || (2 * width == width_ && 2 * height == height_);
  if (copied && !clipped_ && prepareCopy(width_, height_)) {
    uploadCopy();
    return;
  }
  glBindTexture(GL_TEXTURE_2D, slotTexture(0));
  if (slotSizes_[0][0] != width || slotSizes_[0][1] != height) {
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    slotSizes_[0] = {width, height};
  }
}

void Overlay2D::drawTexelsQuad(float x, float y, float w, float h) {
  // The texels as they are: replace, the same pixels as modulating by opaque white with a
  // simpler fragment program for the software rasteriser.
  glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
  glColor4f(1, 1, 1, 1);
  drawQuad2D(x, y, w, h, 0, 0, 1, 1);
  glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
}

bool Overlay2D::copyAvailable() {
  if (copyState_ != 0) return copyState_ > 0;
  copyState_ = -1;
  const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  const bool core = version != nullptr && std::atoi(version) >= 3;
  if (!core && !SDL_GL_ExtensionSupported("GL_ARB_framebuffer_object")) return false;
  // A blit into a multisampled window is an error (GL 3.0): such a window keeps the quad.
  GLint sampleBuffers = 0;
  glGetIntegerv(GL_SAMPLE_BUFFERS, &sampleBuffers);
  if (sampleBuffers != 0) return false;
  copy_.genFramebuffers = SDL_GL_GetProcAddress("glGenFramebuffers");
  copy_.deleteFramebuffers = SDL_GL_GetProcAddress("glDeleteFramebuffers");
  copy_.bindFramebuffer = SDL_GL_GetProcAddress("glBindFramebuffer");
  copy_.framebufferTexture2D = SDL_GL_GetProcAddress("glFramebufferTexture2D");
  copy_.checkFramebufferStatus = SDL_GL_GetProcAddress("glCheckFramebufferStatus");
  copy_.blitFramebuffer = SDL_GL_GetProcAddress("glBlitFramebuffer");
  if (copy_.genFramebuffers == nullptr || copy_.deleteFramebuffers == nullptr || copy_.bindFramebuffer == nullptr ||
      copy_.framebufferTexture2D == nullptr || copy_.checkFramebufferStatus == nullptr ||
      copy_.blitFramebuffer == nullptr)
    return false;
  copyState_ = 1;
  return true;
}

bool Overlay2D::prepareCopy(int width, int height) {
  if (!copyAvailable()) return false;
  if (copySize_[0] == width && copySize_[1] == height) return true;
  const auto bindFramebuffer = reinterpret_cast<PFNGLBINDFRAMEBUFFERPROC>(copy_.bindFramebuffer);
  if (copyTexture_ == 0) glGenTextures(1, &copyTexture_);
  glBindTexture(GL_TEXTURE_2D, copyTexture_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  // Unsized GL_RGBA with BGRA data: Mesa keeps the bytes as they are (B8G8R8A8, the window's
  // order), so neither the upload nor the blit converts.
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, width, height, 0, GL_BGRA, GL_UNSIGNED_INT_8_8_8_8_REV, nullptr);
  if (copyFramebuffer_ == 0) reinterpret_cast<PFNGLGENFRAMEBUFFERSPROC>(copy_.genFramebuffers)(1, &copyFramebuffer_);
  bindFramebuffer(GL_READ_FRAMEBUFFER, copyFramebuffer_);
  reinterpret_cast<PFNGLFRAMEBUFFERTEXTURE2DPROC>(copy_.framebufferTexture2D)(
      GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, copyTexture_, 0);
  const GLenum status = reinterpret_cast<PFNGLCHECKFRAMEBUFFERSTATUSPROC>(copy_.checkFramebufferStatus)(GL_READ_FRAMEBUFFER);
  bindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    copyState_ = -1;
    return false;
  }
  copySize_ = {width, height};
  copyPixels_.resize(size_t(width) * size_t(height) * 4);
  return true;
}

void Overlay2D::uploadCopy() {
  glBindTexture(GL_TEXTURE_2D, copyTexture_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, copySize_[0], copySize_[1], GL_BGRA, GL_UNSIGNED_INT_8_8_8_8_REV,
                  copyPixels_.data());
}

void Overlay2D::blitCopy(int x, int y) {
  const int w = copySize_[0], h = copySize_[1];
  uploadCopy();
  // Texture row 0 is the picture's top row; GL counts window rows from the bottom, so the copy
  // runs from the rectangle's top edge down (as the window stores its rows: no flip for Mesa).
  const auto bindFramebuffer = reinterpret_cast<PFNGLBINDFRAMEBUFFERPROC>(copy_.bindFramebuffer);
  bindFramebuffer(GL_READ_FRAMEBUFFER, copyFramebuffer_);
  reinterpret_cast<PFNGLBLITFRAMEBUFFERPROC>(copy_.blitFramebuffer)(
      0, 0, w, h, x, height_ - y, x + w, height_ - (y + h), GL_COLOR_BUFFER_BIT, GL_NEAREST);
  bindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

bool Overlay2D::copyPicture(const uint8_t* rgba, int width, int height, float x, float y, float w, float h) {
  if (clipped_) return false;
  const int ix = static_cast<int>(x), iy = static_cast<int>(y);
  const int iw = static_cast<int>(w), ih = static_cast<int>(h);
  if (static_cast<float>(ix) != x || static_cast<float>(iy) != y || static_cast<float>(iw) != w ||
      static_cast<float>(ih) != h)
    return false;
  if (ix < 0 || iy < 0 || iw <= 0 || ih <= 0 || ix + iw > width_ || iy + ih > height_) return false;
  const bool sameSize = iw == width && ih == height;
  if (!sameSize && (iw != 2 * width || ih != 2 * height)) return false;
  if (!prepareCopy(iw, ih)) return false;
  if (sameSize) copyRgbaToBgra(rgba, width, height, copyPixels_.data());
  else upscale2xRgbaToBgra(rgba, width, height, copyPixels_.data(), upscaleRows_);
  blitCopy(ix, iy);
  return true;
}

std::vector<uint8_t> Overlay2D::readPixelsRGB(int width, int height) const {
  std::vector<uint8_t> pixels(static_cast<size_t>(width) * height * 3);
  if (pixels.empty()) return pixels;
  flushPics();
  clearIfPending();
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  // GL rows start at the bottom: flip to top-first.
  const size_t row = static_cast<size_t>(width) * 3;
  std::vector<uint8_t> line(row);
  for (int y = 0; y < height / 2; ++y) {
    uint8_t* a = &pixels[y * row];
    uint8_t* b = &pixels[(height - 1 - y) * row];
    std::copy(a, a + row, line.begin());
    std::copy(b, b + row, a);
    std::copy(line.begin(), line.end(), b);
  }
  return pixels;
}

void Overlay2D::release() {
  batch_.quads.clear();   // their textures go with the context
  for (unsigned& texture : slotTextures_)
    if (texture != 0) glDeleteTextures(1, &texture);
  slotTextures_.clear();
  slotSizes_.clear();
  if (copyFramebuffer_ != 0 && copy_.deleteFramebuffers != nullptr)
    reinterpret_cast<PFNGLDELETEFRAMEBUFFERSPROC>(copy_.deleteFramebuffers)(1, &copyFramebuffer_);
  if (copyTexture_ != 0) glDeleteTextures(1, &copyTexture_);
  copyFramebuffer_ = copyTexture_ = 0;
  copySize_ = {0, 0};
  copy_ = {};
  copyState_ = 0;
}

}  // namespace glue
