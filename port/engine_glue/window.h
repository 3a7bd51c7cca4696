#pragma once
// The SDL2 window and its OpenGL context: created on the first BeginRegistration, sized by
// r_mode / r_customwidth / r_customheight / r_fullscreen, described to the engine in glconfig_t.
#include <string>

#include "port/engine_glue/ioq3_abi.h"

struct SDL_Window;

namespace glue {

/// Requested video mode, read from the cvars.
struct VideoModeRequest {
  int mode = -2;             ///< r_mode: index into the stock table, -1 custom, -2 desktop.
  int customWidth = 1600;    ///< r_customwidth
  int customHeight = 1024;   ///< r_customheight
  bool fullscreen = false;   ///< r_fullscreen
};

/// Width and height for a stock mode number; false when the number is not in the table.
bool stockVideoMode(int mode, int& width, int& height);

/// Owns the SDL window and GL context. Not copyable.
class Window {
 public:
  Window() = default;
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  /// Creates the window and GL context (throws FatalError) and fills config.
  void open(const VideoModeRequest& request, q3abi::glconfig_t& config);
  /// Destroys the context and window and quits the SDL video subsystem. Idempotent.
  void close();
  /// True between open() and close().
  bool isOpen() const { return window_ != nullptr; }
  /// Presents the back buffer.
  void swap();
  /// The SDL window (handed to the engine's input code).
  SDL_Window* sdlWindow() const { return window_; }
  /// Drawable size in pixels.
  int width() const { return width_; }
  int height() const { return height_; }
  /// True when the picture (width() x height()) is the whole drawable surface.
  bool pictureFillsSurface() const { return fillsSurface_; }

 private:
  SDL_Window* window_ = nullptr;
  void* glContext_ = nullptr;
  int width_ = 0;
  int height_ = 0;
  bool fillsSurface_ = true;
};

}  // namespace glue
