#pragma once
// GlbBuilder: assembles a binary glTF 2.0 file (.glb) with every buffer and image embedded
// in the one BIN chunk. Owns the JSON document and the binary buffer; callers add views,
// accessors and images and fill in the rest of the JSON (meshes, materials, nodes) directly.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <nlohmann/json.hpp>

namespace pa::converter {

/// glTF bufferView.target values.
enum class BufferTarget : int { None = 0, ArrayBuffer = 34962, ElementArrayBuffer = 34963 };

/// Builds one .glb: JSON chunk + BIN chunk, 4-byte aligned as the spec requires.
class GlbBuilder {
 public:
  /// Starts a document with asset.generator set.
  explicit GlbBuilder(std::string generator);

  /// The glTF JSON document (add meshes, materials, nodes, extensions here).
  nlohmann::json& json() { return doc_; }

  /// Appends raw bytes to the BIN chunk as a new bufferView; returns its index.
  uint32_t addBufferView(std::span<const std::byte> bytes, BufferTarget target);

  /// Float VEC3 attribute accessor (min/max written: required for POSITION, harmless elsewhere).
  uint32_t addVec3(std::span<const glm::vec3> values);
  /// Float VEC2 attribute accessor (texture coordinates).
  uint32_t addVec2(std::span<const glm::vec2> values);
  /// Float VEC4 attribute accessor.
  uint32_t addVec4(std::span<const glm::vec4> values);
  /// Index accessor: UNSIGNED_SHORT when every index fits, else UNSIGNED_INT.
  uint32_t addIndices(std::span<const uint32_t> indices);

  /// Encodes RGBA8 pixels as PNG into the BIN chunk; returns the glTF image index.
  /// Throws std::runtime_error when the encoder fails.
  uint32_t addPngImage(uint32_t width, uint32_t height, std::span<const uint8_t> rgba8, const std::string& name);

  /// Adds `name` to extensionsUsed (once); also to extensionsRequired when required.
  void useExtension(const std::string& name, bool required = false);

  /// Appends an element to a top-level array (creating it) and returns its index.
  uint32_t append(const char* arrayName, nlohmann::json element);

  /// Serialises the document and the buffer into GLB bytes.
  std::vector<std::byte> finish();

 private:
  uint32_t addAccessor(uint32_t view, int componentType, size_t count, const char* type,
                       nlohmann::json min, nlohmann::json max);
  nlohmann::json doc_;
  std::vector<std::byte> bin_;
};

/// Encodes RGBA8 pixels as PNG bytes (stb_image_write); empty on failure.
std::vector<std::byte> encodePng(uint32_t width, uint32_t height, std::span<const uint8_t> rgba8);

}  // namespace pa::converter
