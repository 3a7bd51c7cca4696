// pa-present-bench [frames]: CPU cost per frame of the ways a 320x180 traced picture can reach a
// 640x360 window through OpenGL (docs/performance.md, "Presentation on llvmpipe"). Each way runs
// `frames` frames (new pixels, draw, swap) in an SDL2 window made as the module makes its own; it
// prints the process's CPU time per frame (all threads: a software GL's rasteriser threads
// included) and the wall time. Run it under the display the game uses, e.g.
//   xvfb-run -a -s "-screen 0 640x360x24" build/port/engine_glue/tests/pa-present-bench 400
#include <SDL.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "port/engine_glue/picture_upscale.h"
#include "port/engine_glue/window_gl_attributes.h"

namespace {

constexpr int kWindowWidth = 640, kWindowHeight = 360, kPictureWidth = 320, kPictureHeight = 180;

double processCpuMs() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return (usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) * 1e3 +
         (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) * 1e-3;
}

void texturedQuad() {
  glBegin(GL_QUADS);
  glTexCoord2f(0, 0); glVertex2f(0, 0);
  glTexCoord2f(1, 0); glVertex2f(kWindowWidth, 0);
  glTexCoord2f(1, 1); glVertex2f(kWindowWidth, kWindowHeight);
  glTexCoord2f(0, 1); glVertex2f(0, kWindowHeight);
  glEnd();
}

struct Way {
  const char* name;
  const char* what;
};

constexpr Way kWays[] = {
    {"quad-bilinear", "320x180 RGBA8 texture, GL_LINEAR quad over the window (the stretch by GL)"},
    {"quad-nearest", "640x360 RGBA8 texture (stretched by us), GL_NEAREST quad 1:1"},
    {"quad-nearest-bgra", "640x360 texture uploaded as GL_BGRA, GL_NEAREST quad 1:1"},
    {"drawpixels", "glDrawPixels of 640x360 RGBA"},
    {"blit-scaled", "320x180 RGBA8 texture in an FBO, glBlitFramebuffer GL_LINEAR to the window"},
    {"blit-rgba", "640x360 RGBA8 texture in an FBO, glBlitFramebuffer 1:1"},
    {"blit-bgra", "640x360 unsized GL_RGBA texture with BGRA bytes, glBlitFramebuffer 1:1 (the module's way)"},
};

}  // namespace

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::max(10, std::atoi(argv[1])) : 400;
  if (SDL_Init(SDL_INIT_VIDEO) != 0) {
    std::fprintf(stderr, "SDL_Init: %s\n", SDL_GetError());
    return 77;
  }
  glue::requestWindowGlAttributes();
  SDL_Window* window = SDL_CreateWindow("pa-present-bench", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                                        kWindowWidth, kWindowHeight, SDL_WINDOW_OPENGL | SDL_WINDOW_SHOWN);
  SDL_GLContext context = window != nullptr ? SDL_GL_CreateContext(window) : nullptr;
  if (context == nullptr) {
    std::fprintf(stderr, "no GL window: %s\n", SDL_GetError());
    return 77;
  }
  SDL_GL_MakeCurrent(window, context);
  SDL_GL_SetSwapInterval(0);
  const auto genFramebuffers = reinterpret_cast<PFNGLGENFRAMEBUFFERSPROC>(SDL_GL_GetProcAddress("glGenFramebuffers"));
  const auto bindFramebuffer = reinterpret_cast<PFNGLBINDFRAMEBUFFERPROC>(SDL_GL_GetProcAddress("glBindFramebuffer"));
  const auto framebufferTexture =
      reinterpret_cast<PFNGLFRAMEBUFFERTEXTURE2DPROC>(SDL_GL_GetProcAddress("glFramebufferTexture2D"));
  const auto blitFramebuffer = reinterpret_cast<PFNGLBLITFRAMEBUFFERPROC>(SDL_GL_GetProcAddress("glBlitFramebuffer"));
  std::printf("%s, %d frames per way\n", reinterpret_cast<const char*>(glGetString(GL_RENDERER)), frames);

  std::vector<uint8_t> picture(size_t(kPictureWidth) * kPictureHeight * 4);
  for (size_t i = 0; i < picture.size(); ++i) picture[i] = static_cast<uint8_t>(i * 7);
  std::vector<uint8_t> window4(size_t(kWindowWidth) * kWindowHeight * 4);
  std::vector<uint16_t> scratch;
  glViewport(0, 0, kWindowWidth, kWindowHeight);
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glOrtho(0, kWindowWidth, kWindowHeight, 0, -1, 1);
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  glDisable(GL_DEPTH_TEST);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);

  for (const Way& way : kWays) {
    const std::string name = way.name;
    const bool half = name == "quad-bilinear" || name == "blit-scaled";
    const bool bgra = name == "quad-nearest-bgra" || name == "blit-bgra";
    const bool blit = name.rfind("blit", 0) == 0;
    const int tw = half ? kPictureWidth : kWindowWidth, th = half ? kPictureHeight : kWindowHeight;
    const GLenum format = bgra ? GL_BGRA : GL_RGBA;
    const GLenum type = bgra ? GL_UNSIGNED_INT_8_8_8_8_REV : GL_UNSIGNED_BYTE;
    const GLint internal = name == "blit-bgra" ? GL_RGBA : GL_RGBA8;
    GLuint texture = 0, framebuffer = 0;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    const GLint filter = half ? GL_LINEAR : GL_NEAREST;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexImage2D(GL_TEXTURE_2D, 0, internal, tw, th, 0, format, type, nullptr);
    if (blit) {
      genFramebuffers(1, &framebuffer);
      bindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
      framebufferTexture(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
      bindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    }
    glEnable(GL_TEXTURE_2D);
    double cpuStart = 0.0, ourMs = 0.0;
    auto wallStart = std::chrono::steady_clock::now();
    const int warmup = 20;
    for (int frame = 0; frame < frames + warmup; ++frame) {
      if (frame == warmup) {
        glFinish();
        cpuStart = processCpuMs();
        wallStart = std::chrono::steady_clock::now();
        ourMs = 0.0;
      }
      picture[size_t(frame) % picture.size()] ^= 1;   // new pixels every frame
      const auto ourStart = std::chrono::steady_clock::now();
      const uint8_t* pixels = picture.data();
      if (!half) {
        glue::upscale2xRgbaToBgra(picture.data(), kPictureWidth, kPictureHeight, window4.data(), scratch);
        pixels = window4.data();
      }
      ourMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - ourStart).count();
      if (name == "drawpixels") {
        glDisable(GL_TEXTURE_2D);
        glRasterPos2i(0, kWindowHeight);
        glPixelZoom(1.0f, 1.0f);
        glDrawPixels(kWindowWidth, kWindowHeight, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
        glEnable(GL_TEXTURE_2D);
      } else {
        glBindTexture(GL_TEXTURE_2D, texture);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, tw, th, format, type, pixels);
        if (blit) {
          bindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
          blitFramebuffer(0, 0, tw, th, 0, kWindowHeight, kWindowWidth, 0, GL_COLOR_BUFFER_BIT, filter);
          bindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        } else {
          texturedQuad();
        }
      }
      SDL_GL_SwapWindow(window);
    }
    glFinish();
    const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wallStart).count();
    const double cpu = processCpuMs() - cpuStart;
    std::printf("%-18s cpu %.3f ms/frame  wall %.3f ms/frame  (CPU stretch %.3f)  %s\n", way.name, cpu / frames,
                wall / frames, ourMs / frames, way.what);
    glDeleteTextures(1, &texture);
  }
  SDL_GL_DeleteContext(context);
  SDL_DestroyWindow(window);
  SDL_Quit();
  return 0;
}
