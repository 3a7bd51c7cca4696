#include "port/engine_glue/window.h"

#include <SDL.h>
#include <GL/gl.h>

#include <algorithm>
#include <cstring>
#include <iterator>

#include "port/engine_glue/engine.h"
#include "port/engine_glue/window_gl_attributes.h"

namespace glue {
namespace {

struct ModeSize {
  int width, height;
};
// ioquake3's stock mode table (r_mode 0..28), so configs written for the stock renderers
// open the same window with ours.
constexpr ModeSize kStockModes[] = {
    {320, 240},   {400, 300},   {512, 384},   {640, 480},   {800, 600},   {960, 720},
    {1024, 768},  {1152, 864},  {1280, 1024}, {1600, 1200}, {2048, 1536}, {856, 480},
    {1280, 720},  {1280, 768},  {1280, 800},  {1280, 960},  {1360, 768},  {1366, 768},
    {1360, 1024}, {1400, 1050}, {1400, 900},  {1600, 900},  {1680, 1050}, {1920, 1080},
    {1920, 1200}, {1920, 1440}, {2560, 1080}, {2560, 1600}, {3840, 2160},
};

void copyString(char* destination, size_t capacity, const char* source) {
  std::snprintf(destination, capacity, "%s", source != nullptr ? source : "");
}

const char* glString(GLenum name) {
  const auto* text = reinterpret_cast<const char*>(glGetString(name));
  return text != nullptr ? text : "";
}

}  // namespace

bool stockVideoMode(int mode, int& width, int& height) {
  if (mode < 0 || mode >= static_cast<int>(std::size(kStockModes))) return false;
  width = kStockModes[mode].width;
  height = kStockModes[mode].height;
  return true;
}

Window::~Window() { close(); }

void Window::open(const VideoModeRequest& request, q3abi::glconfig_t& config) {
  if (window_ != nullptr) return;
  if (!SDL_WasInit(SDL_INIT_VIDEO) && SDL_InitSubSystem(SDL_INIT_VIDEO) != 0)
    throw FatalError(std::string("SDL video init failed: ") + SDL_GetError());

  int width = 0, height = 0;
  SDL_DisplayMode desktop{};
  const bool haveDesktop = SDL_GetDesktopDisplayMode(0, &desktop) == 0;
  if (request.mode == -1) {
    width = std::clamp(request.customWidth, 64, 16384);
    height = std::clamp(request.customHeight, 64, 16384);
  } else if (!stockVideoMode(request.mode, width, height)) {  // -2 or unknown: desktop size
    width = haveDesktop ? desktop.w : 1280;
    height = haveDesktop ? desktop.h : 720;
  }

  requestWindowGlAttributes();
  Uint32 flags = SDL_WINDOW_OPENGL | SDL_WINDOW_SHOWN;
  if (request.fullscreen) flags |= SDL_WINDOW_FULLSCREEN;
  window_ = SDL_CreateWindow("OpenArena (PathArena path tracer)", SDL_WINDOWPOS_CENTERED,
                             SDL_WINDOWPOS_CENTERED, width, height, flags);
  if (window_ == nullptr) {
    // Some drivers refuse a stencil buffer or 24-bit depth: retry with the bare minimum.
    SDL_GL_SetAttribute(SDL_GL_STENCIL_SIZE, 0);
    SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 16);
    window_ = SDL_CreateWindow("OpenArena (PathArena path tracer)", SDL_WINDOWPOS_CENTERED,
                               SDL_WINDOWPOS_CENTERED, width, height, flags);
  }
  if (window_ == nullptr)
    throw FatalError(std::string("SDL_CreateWindow failed: ") + SDL_GetError());
  glContext_ = SDL_GL_CreateContext(window_);
  if (glContext_ == nullptr) {
    const std::string reason = SDL_GetError();
    close();
    throw FatalError("SDL_GL_CreateContext failed: " + reason);
  }
  SDL_GL_MakeCurrent(window_, glContext_);
  SDL_GL_SetSwapInterval(0);  // the path tracer sets the pace; never wait for vsync twice
  SDL_GL_GetDrawableSize(window_, &width_, &height_);
  if (request.fullscreen) {
    // As stock: a fullscreen picture is the requested mode's size, drawn from the bottom-left of
    // whatever the display gave (a display without that mode keeps its own size: under Xvfb a
    // 640x360 request yields a 1024x768 surface with the 640x360 picture in its corner, and
    // screenshots read the 640x360 picture).
    fillsSurface_ = width_ == width && height_ == height;
    width_ = width;
    height_ = height;
  } else {
    fillsSurface_ = true;
  }

  std::memset(&config, 0, sizeof config);
  copyString(config.renderer_string, sizeof config.renderer_string, glString(GL_RENDERER));
  copyString(config.vendor_string, sizeof config.vendor_string, glString(GL_VENDOR));
  copyString(config.version_string, sizeof config.version_string, glString(GL_VERSION));
  copyString(config.extensions_string, sizeof config.extensions_string, glString(GL_EXTENSIONS));
  GLint maxTexture = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
  config.maxTextureSize = maxTexture;
  config.numTextureUnits = 1;
  int red = 0, green = 0, blue = 0, depth = 0, stencil = 0;
  SDL_GL_GetAttribute(SDL_GL_RED_SIZE, &red);
  SDL_GL_GetAttribute(SDL_GL_GREEN_SIZE, &green);
  SDL_GL_GetAttribute(SDL_GL_BLUE_SIZE, &blue);
  SDL_GL_GetAttribute(SDL_GL_DEPTH_SIZE, &depth);
  SDL_GL_GetAttribute(SDL_GL_STENCIL_SIZE, &stencil);
  config.colorBits = red + green + blue;
  config.depthBits = depth;
  config.stencilBits = stencil;
  // r_gamma is honoured with a software ramp over the finished frame (the menu's brightness
  // slider needs this set); overbright bits stay 0 (settings.h PictureSettings).
  config.deviceSupportsGamma = 1;
  config.textureEnvAddAvailable = 1;
  config.vidWidth = width_;
  config.vidHeight = height_;
  config.windowAspect = height_ > 0 ? static_cast<float>(width_) / static_cast<float>(height_) : 1.0f;
  SDL_DisplayMode current{};
  config.displayFrequency =
      SDL_GetWindowDisplayMode(window_, &current) == 0 ? current.refresh_rate : 60;
  config.isFullscreen = request.fullscreen ? 1 : 0;
}

void Window::close() {
  if (glContext_ != nullptr) {
    SDL_GL_MakeCurrent(window_, nullptr);
    SDL_GL_DeleteContext(static_cast<SDL_GLContext>(glContext_));
    glContext_ = nullptr;
  }
  if (window_ != nullptr) {
    SDL_DestroyWindow(window_);
    window_ = nullptr;
    SDL_QuitSubSystem(SDL_INIT_VIDEO);
  }
  width_ = height_ = 0;
}

void Window::swap() {
  if (window_ != nullptr) SDL_GL_SwapWindow(window_);
}

}  // namespace glue
