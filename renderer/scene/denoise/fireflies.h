#pragma once
// Firefly spreading, for a frame after temporal accumulation and before the à-trous filter: a
// rare, very bright sample (a small intense emitter found by one light sample in many, a caustic
// path) lands on one pixel as a speck that the history keeps for frames and the filter's
// luminance weight keeps sharp. Here each
// pixel's lit radiance (radiance - emission) whose luminance passes `ratio` times the mean of its
// neighbourhood (the window around it, itself left out) is cut to that level, and what was cut is
// shared equally among the pixels of its window that see the same surface (similar normal and
// depth), itself included. The frame's lit radiance is kept exactly: no darkening, unlike a
// clamp; the speck becomes a faint local glow that the filters average like any other light.
// Emission (what the camera sees of emitters) and sky pixels (depth inf) are never touched.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace pa::denoise {

/// When a pixel counts as a firefly and where its excess goes.
struct FireflyConfig {
  float ratio = 4.0f;           ///< A pixel is cut to this many times its neighbourhood's mean luminance.
  float floor = 0.05f;          ///< ... but never below this luminance (dim noise is left alone).
  uint32_t radius = 2;          ///< Window half-width: 2 = 5 x 5 pixels.
  float normalCosine = 0.8f;    ///< Least cosine between the normals of a pixel and a receiver.
  float depthTolerance = 0.1f;  ///< Largest relative depth difference of a receiver.
};

/// One frame's guides (width * height each, row-major from the top row), as the film resolves them.
struct FireflyInputs {
  uint32_t width = 0;
  uint32_t height = 0;
  std::span<const glm::vec3> emission;   ///< Part of the radiance left alone (Film::emission).
  std::span<const glm::vec3> normal;     ///< Mean first-hit shading normal.
  std::span<const float> depth;          ///< Mean first-hit distance (inf = sky).
};

/// spreadFireflies' working arrays; one kept from frame to frame makes the pass allocate nothing
/// once the frame size is stable.
struct FireflyScratch {
  std::vector<float> luminance, share;
  std::vector<double> luminanceSums;
  std::vector<uint32_t> geometrySums;
  std::vector<glm::vec3> excess, out;
  std::vector<uint8_t> rowCuts;
};

/// Cuts and spreads the fireflies of `radiance` in place; returns how many pixels were cut. Parallel
/// over rows in the calling task arena; the result does not depend on the thread count. Throws
/// std::invalid_argument when a span's size is not width * height.
uint32_t spreadFireflies(const FireflyInputs& in, std::span<glm::vec3> radiance, const FireflyConfig& config = {});
/// The same with the caller's working arrays.
uint32_t spreadFireflies(const FireflyInputs& in, std::span<glm::vec3> radiance, FireflyScratch& scratch,
                         const FireflyConfig& config = {});

}  // namespace pa::denoise
