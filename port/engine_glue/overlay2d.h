#pragma once
// Draws a frame with OpenGL strictly in the engine's call order: traced 3D views as textured
// rectangles, then SetColor / DrawStretchPic / DrawStretchRaw 2D quads with their shader's blend
// mode and alpha test. Coordinates are window pixels, origin top-left (as the engine gives them).
// Consecutive DrawStretchPics of one shader are drawn together, as the stock renderer batches
// them (a line of text is one draw, not one per character): on a software GL each draw's state
// validation and set-up costs CPU. Every other drawing call draws the waiting quads first.
// An opaque view picture of the rectangle's size or half of it is stretched on the CPU
// (picture_upscale.h) and copied into the window with glBlitFramebuffer, which Mesa's llvmpipe
// executes as a memory copy when the pixels are in the window's byte order; a textured quad
// would run a fragment program per window pixel.
#include <array>
#include <cstdint>
#include <vector>

#include "port/engine_glue/ioq3_abi.h"
#include "port/engine_glue/overlay_stages.h"
#include "port/engine_glue/shaders.h"

namespace glue {

class Engine;

/// Immediate 2D drawing into the window's back buffer.
class Overlay2D {
 public:
  /// Textures kept for 3D views (a view keeps its slot's texture when its size is unchanged).
  static constexpr int kViewSlots = 8;

  Overlay2D() = default;
  ~Overlay2D() = default;
  Overlay2D(const Overlay2D&) = delete;
  Overlay2D& operator=(const Overlay2D&) = delete;

  /// Starts a frame: viewport, projection, black background. The clear is done before the
  /// first draw, and skipped when that draw is an opaque picture over the whole window and the
  /// window is the whole drawable surface (`fillsSurface`).
  void beginFrame(int width, int height, bool fillsSurface = true);
  /// Ends the frame's drawing: a frame with nothing drawn is cleared now.
  void finishDrawing();
  /// SetColor (nullptr = opaque white).
  void setColor(const float* rgba);
  /// DrawStretchPic: every stage of a scripted shader (see overlay_stages.h), else the image.
  /// `images` reads the stage images of a scripted shader on its first 2D draw. The quad is
  /// drawn with the next one of another shader or time, or before any other drawing.
  void drawPic(ShaderRegistry& shaders, const Engine& engine, const ImageSource& images, q3abi::qhandle_t shader,
               double seconds, float x, float y, float w, float h, float s1, float t1, float s2, float t2);
  /// Draws RGBA8 pixels (width*height, top row first) stretched over a rectangle; when not
  /// `opaque` the colours are premultiplied by alpha (alpha 0 still adds its colour).
  /// `slot` in [0, kViewSlots) picks a reusable texture: give each view of a frame its own, so
  /// that views of different sizes do not re-create one texture back and forth.
  void drawPixels(int slot, const uint8_t* rgba, int width, int height, float x, float y, float w,
                  float h, bool opaque);
  /// While a map loads, does what the first frame of play would wait for: draws a see-through
  /// model view's state once (Mesa's llvmpipe compiles a program for each new state at its first
  /// draw: 10-14 ms) and makes the GL storage of a world picture of width x height shown over the
  /// whole window (the copy's texture, else slot 0's; 0 x 0: none).
  void prepareForPlay(int width, int height);
  /// UploadCinematic: replaces a cinematic slot's pixels (RGBA8 `cols` x `rows`).
  void uploadRaw(int client, const uint8_t* rgba, int cols, int rows);
  /// DrawStretchRaw after an upload: draws that cinematic slot.
  void drawRaw(int client, float x, float y, float w, float h);
  /// Limits drawing to a rectangle in window pixels (top-left origin) until clearClip().
  void clip(int x, int y, int w, int h);
  /// Draws over the whole window again.
  void clearClip();
  /// Maps every colour byte of the frame (the beginFrame size from the bottom-left) through
  /// `ramp` (a gamma ramp applied in software): read back, mapped, copied (or drawn) again.
  void applyRamp(const std::array<uint8_t, 256>& ramp);
  /// Reads the back buffer as RGB8 rows, top row first.
  std::vector<uint8_t> readPixelsRGB(int width, int height) const;
  /// Deletes the GL objects (context must be current).
  void release();

 private:
  /// Framebuffer-object entry points of the context (SDL_GL_GetProcAddress), when it has them.
  struct CopyFunctions {
    void* genFramebuffers = nullptr;
    void* deleteFramebuffers = nullptr;
    void* bindFramebuffer = nullptr;
    void* framebufferTexture2D = nullptr;
    void* checkFramebufferStatus = nullptr;
    void* blitFramebuffer = nullptr;
  };
  /// Loads CopyFunctions once per context; false when the context has no framebuffer blits.
  bool copyAvailable();
  /// Sizes the copy's texture (and copyPixels_) to width x height; false without framebuffer blits.
  bool prepareCopy(int width, int height);
  /// Uploads copyPixels_ (BGRA, top row first) into the copy's texture.
  void uploadCopy();
  /// Uploads copyPixels_ (BGRA, top row first) and copies it to the window at (x, y), top-left.
  void blitCopy(int x, int y);
  /// Copies an opaque picture into the window rectangle (its size, or twice its size with the
  /// bilinear stretch); false when the context or the rectangle does not allow it.
  bool copyPicture(const uint8_t* rgba, int width, int height, float x, float y, float w, float h);
  unsigned slotTexture(int slot);
  /// Replaces a slot's pixels (re-creating its texture only when the size changes).
  void upload(int slot, const uint8_t* rgba, int width, int height);
  /// Draws the bound texture's texels unmodulated over a rectangle (blend state as set).
  void drawTexelsQuad(float x, float y, float w, float h);
  /// Clears the whole window if beginFrame's clear is still due.
  void clearIfPending() const;
  /// Draws the DrawStretchPic quads waiting in the batch.
  void flushPics() const;

  /// DrawStretchPic quads of one shader at one time, waiting to be drawn together.
  struct PicBatch {
    ShaderRegistry* shaders = nullptr;
    q3abi::qhandle_t shader = 0;
    double seconds = 0.0;
    bool stages = false;              ///< A scripted shader: drawStages2D.
    std::vector<unsigned> textures;   ///< Per stage (scripted), else the image's texture.
    std::vector<Quad2D> quads;
  };

  int width_ = 0;
  int height_ = 0;
  std::array<float, 4> color_{1, 1, 1, 1};
  bool fillsSurface_ = true;            ///< The window is the whole drawable surface.
  bool clipped_ = false;                ///< A clip() rectangle is in force.
  mutable bool clearPending_ = false;   ///< beginFrame's clear is not done yet.
  std::vector<unsigned> slotTextures_;   ///< Views, then kViewSlots + client for cinematics
  std::vector<std::array<int, 2>> slotSizes_;
  std::vector<uint8_t> rampPixels_;   ///< applyRamp's frame copy.
  int copyState_ = 0;                 ///< Picture copies: 0 not tried yet, 1 available, -1 not.
  unsigned copyTexture_ = 0;          ///< The BGRA picture the copy reads (window rectangle size).
  unsigned copyFramebuffer_ = 0;      ///< Read framebuffer holding copyTexture_.
  std::array<int, 2> copySize_{0, 0};
  CopyFunctions copy_;
  std::vector<uint8_t> copyPixels_;     ///< The stretched picture, BGRA.
  std::vector<uint16_t> upscaleRows_;   ///< upscale2xRgbaToBgra's working row.
  mutable PicBatch batch_;
};

}  // namespace glue
