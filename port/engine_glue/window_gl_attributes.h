#pragma once
// The GL framebuffer the game's window asks SDL for (the module's window and pa-present-bench,
// which measures presentation into the same kind of window).
#include <SDL.h>

namespace glue {

/// Requests 8-bit RGB, 24-bit depth, 8-bit stencil and double buffering for the next window.
inline void requestWindowGlAttributes() {
  SDL_GL_SetAttribute(SDL_GL_RED_SIZE, 8);
  SDL_GL_SetAttribute(SDL_GL_GREEN_SIZE, 8);
  SDL_GL_SetAttribute(SDL_GL_BLUE_SIZE, 8);
  SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 24);
  SDL_GL_SetAttribute(SDL_GL_STENCIL_SIZE, 8);
  SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
}

}  // namespace glue
