#pragma once
// Shader handles: RegisterShader / RegisterShaderNoMip / RemapShader. Handle 0 is the default
// shader (what the stock renderer returns for anything it cannot find). Each entry keeps its
// decoded images (for the path tracer's materials) and lazily created GL textures (for 2D).
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "port/engine_glue/images.h"
#include "port/engine_glue/ioq3_abi.h"
#include "port/engine_glue/shader_scripts.h"

namespace glue {

/// One script stage's images for 2D drawing, decoded and uploaded on its first 2D draw (most
/// registered shaders are only ever traced, so registration does not read their stage images).
struct StageTextures {
  std::vector<unsigned> glTextures;                   ///< One per map/animMap frame once drawn.
  bool clamp = false;                                 ///< clampMap (or a no-mip 2D registration).
};

/// Reads an image by name (nullptr when it cannot be read).
using ImageSource = std::function<std::shared_ptr<const Image>(const std::string&)>;

/// One registered shader.
struct ShaderEntry {
  std::string name;                                   ///< As registered (normalised).
  ShaderLook look;
  std::vector<std::shared_ptr<const Image>> frames;   ///< look.images decoded (default on failure).
  std::vector<std::vector<std::shared_ptr<const Image>>> layerFrames;   ///< Per look.layers.
  std::shared_ptr<const Image> shineImage;            ///< look.shine's image (null when none or missing).
  std::vector<unsigned> glTextures;                   ///< Lazily uploaded, one per frame.
  std::vector<StageTextures> stageTextures;           ///< Per look.stages (empty for non-images).
  bool clampToEdge = false;
  q3abi::qhandle_t remappedTo = 0;                    ///< RemapShader target (0 = none).
  float remapTimeOffset = 0.0f;
  bool isDefault = false;
};

/// The table of shader handles. GL calls need the module's context to be current.
class ShaderRegistry {
 public:
  ShaderRegistry();
  ~ShaderRegistry() = default;
  ShaderRegistry(const ShaderRegistry&) = delete;
  ShaderRegistry& operator=(const ShaderRegistry&) = delete;

  /// Registers (or finds) a shader for 2D or model use. 0 when it cannot be made.
  q3abi::qhandle_t registerShader(const Engine& engine, const ShaderScripts& scripts,
                                  ImageCache& images, std::string_view name, bool mipmaps);
  /// The entry for a handle, following RemapShader; the default entry for bad handles.
  const ShaderEntry& resolve(q3abi::qhandle_t handle) const;
  /// Entry by handle without remapping (nullptr when out of range).
  ShaderEntry* entry(q3abi::qhandle_t handle);
  /// RemapShader: draw `newName` wherever `oldName` is used.
  void remap(const Engine& engine, const ShaderScripts& scripts, ImageCache& images,
             const std::string& oldName, const std::string& newName, float timeOffset);
  /// The GL texture of a handle's (remapped) shader at its current animation frame
  /// (uploads on first use).
  unsigned glTexture(q3abi::qhandle_t handle, double seconds);
  /// The GL texture of stage `stage` of a handle's (remapped) shader at its current animMap
  /// frame; the stage's images are read through `images` and uploaded on first use (the default
  /// image, with a warning, for one that cannot be read; white for stages without images).
  unsigned stageGlTexture(const Engine& engine, const ImageSource& images, q3abi::qhandle_t handle, size_t stage,
                          double seconds);
  /// Number of handles, including the default one.
  int count() const { return static_cast<int>(entries_.size()); }
  /// Finds a registered handle by name (0 when absent).
  q3abi::qhandle_t find(std::string_view name) const;
  /// Deletes GL textures (the context must be current) and every entry but the default one.
  void clear();

 private:
  size_t resolveIndex(q3abi::qhandle_t handle) const;

  std::vector<ShaderEntry> entries_;
  /// A name as byName_ keys it (normalizeName(stripExtension(name))), made on the stack.
  struct LookupKey {
    explicit LookupKey(std::string_view name);
    char text[q3abi::kMaxQPath];
    size_t length = 0;
    std::string_view view() const { return {text, length}; }
  };
  /// Hashes names and their views alike, so that find() looks up without making a string.
  struct NameHash {
    using is_transparent = void;
    size_t operator()(std::string_view name) const { return std::hash<std::string_view>{}(name); }
  };
  std::unordered_map<std::string, q3abi::qhandle_t, NameHash, std::equal_to<>> byName_;   ///< Includes failures -> 0.
};

}  // namespace glue
