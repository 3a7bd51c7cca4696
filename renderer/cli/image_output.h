#pragma once
// Writing rendered frames: 8-bit PNG (stb_image_write) and float OpenEXR with AOV layers (tinyexr).
#include <cstdint>
#include <filesystem>
#include <span>

#include <glm/vec3.hpp>

namespace pa::cli {

/// Linear buffers of one frame, width*height each, row-major from the top row.
struct ExrLayers {
  uint32_t width = 0;
  uint32_t height = 0;
  std::span<const glm::vec3> radiance;   ///< Written as R, G, B.
  std::span<const glm::vec3> albedo;     ///< albedo.R/G/B (skipped if empty).
  std::span<const glm::vec3> normal;     ///< normal.X/Y/Z (skipped if empty).
  std::span<const float> depth;          ///< Z (skipped if empty).
  std::span<const float> variance;       ///< variance.Y (skipped if empty).
};

/// Writes RGBA8 pixels as a PNG; creates missing parent folders. Throws std::runtime_error.
void writePng(const std::filesystem::path& path, uint32_t width, uint32_t height, std::span<const uint8_t> rgba8);

/// Writes a single-part scanline OpenEXR (32-bit float, ZIP) with all non-empty layers.
/// Creates missing parent folders. Throws std::runtime_error.
void writeExr(const std::filesystem::path& path, const ExrLayers& layers);

}  // namespace pa::cli
