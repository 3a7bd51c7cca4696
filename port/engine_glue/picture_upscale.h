#pragma once
// A traced picture made ready for a plain copy into the window: RGBA8 in, BGRA8 out (the byte
// order of the window's pixels under Mesa, so that the GL driver copies instead of converting),
// either the same size or stretched 2x with the bilinear filter GL applies to a texture drawn
// over twice its size (texel centres at half-integers, edges clamped), in SIMD on the CPU.
#include <cstdint>
#include <vector>

namespace glue {

/// Copies `width` x `height` RGBA8 pixels to BGRA8 (rows in the same order).
void copyRgbaToBgra(const uint8_t* rgba, int width, int height, uint8_t* bgra);

/// Writes the (2*width) x (2*height) BGRA8 bilinear stretch of `width` x `height` RGBA8 pixels:
/// each output value is (9a + 3b + 3c + d) / 16 of its four nearest texels, rounded half up (the
/// weights of GL's bilinear filter at a 2x stretch). `scratch` is working memory kept by the
/// caller (grown on the first call at a size, reused afterwards).
void upscale2xRgbaToBgra(const uint8_t* rgba, int width, int height, uint8_t* bgra,
                         std::vector<uint16_t>& scratch);

}  // namespace glue
