#pragma once
// Model and skin handles: RegisterModel (MD3 files, inline "*N" brush models), RegisterSkin,
// LerpTag and ModelBounds. MD3 files are parsed by q3formats (q3::parseMd3), like the converter. Handle 0 is "no model" / "no skin", like the stock renderer.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "port/engine_glue/engine.h"
#include "port/engine_glue/ioq3_abi.h"
#include "port/q3formats/model/md3.h"
#include "port/q3formats/model/skin.h"

namespace glue {

class Engine;

/// Kinds of registered models.
enum class ModelKind : uint8_t { Bad, Md3, Brush };

/// One registered model.
struct ModelEntry {
  std::string name;
  ModelKind kind = ModelKind::Bad;
  int brushIndex = 0;                         ///< Brush: the world's submodel number.
  std::vector<std::shared_ptr<const q3::Md3Model>> lods;   ///< Md3: LOD 0 first (q3formats).
};

/// One skin: surface name -> shader handle.
struct SkinEntry {
  std::string name;
  std::vector<std::pair<std::string, q3abi::qhandle_t>> surfaces;
};

/// Model and skin tables.
class ModelRegistry {
 public:
  ModelRegistry();
  /// Registers an MD3 (with its _1/_2 LODs) or an inline brush model "*N". 0 on failure.
  q3abi::qhandle_t registerModel(const Engine& engine, const std::string& name,
                                 int worldSubmodelCount);
  /// The entry for a handle (nullptr for 0 or out of range).
  const ModelEntry* model(q3abi::qhandle_t handle) const;
  /// Registers a skin from its .skin lines; `registerShader` maps shader names to handles.
  template <typename RegisterShader>
  q3abi::qhandle_t registerSkin(const Engine& engine, const std::string& name,
                                RegisterShader&& registerShader);
  /// The entry for a skin handle (nullptr for 0 or out of range).
  const SkinEntry* skin(q3abi::qhandle_t handle) const;
  /// LerpTag: false (identity) when the model or tag is unknown.
  bool lerpTag(q3abi::orientation_t& out, q3abi::qhandle_t model, int startFrame, int endFrame,
               float frac, const std::string& tagName) const;
  /// ModelBounds of an MD3 (frame 0); brush bounds come from the world.
  bool md3Bounds(q3abi::qhandle_t model, glm::vec3& mins, glm::vec3& maxs) const;
  /// Forgets every model and skin (map change).
  void clear();
  /// Number of model handles including 0.
  int modelCount() const { return static_cast<int>(models_.size()); }

 private:
  q3abi::qhandle_t addSkin(SkinEntry skin);
  std::vector<ModelEntry> models_;
  std::unordered_map<std::string, q3abi::qhandle_t> modelsByName_;
  std::vector<SkinEntry> skins_;
  std::unordered_map<std::string, q3abi::qhandle_t> skinsByName_;
};

template <typename RegisterShader>
q3abi::qhandle_t ModelRegistry::registerSkin(const Engine& engine, const std::string& name,
                                             RegisterShader&& registerShader) {
  const std::string key = normalizeName(name);
  if (const auto found = skinsByName_.find(key); found != skinsByName_.end()) return found->second;
  SkinEntry skin;
  skin.name = key;
  if (key.size() < 5 || key.compare(key.size() - 5, 5, ".skin") != 0) {
    // Not a .skin file: the whole model uses this one shader.
    skin.surfaces.emplace_back("*", registerShader(name));
    return addSkin(std::move(skin));
  }
  const auto bytes = engine.readFile(name);
  if (!bytes) {
    engine.warn("RegisterSkin: couldn't load " + name);
    skinsByName_.emplace(key, 0);
    return 0;
  }
  const std::string_view text(reinterpret_cast<const char*>(bytes->data()), bytes->size());
  const q3::Skin parsed = q3::parseSkin(text, name);
  for (const std::string& warning : parsed.warnings)
    engine.print(q3abi::PRINT_DEVELOPER, "RegisterSkin: %s\n", warning.c_str());
  for (const q3::SkinSurface& surface : parsed.surfaces)
    skin.surfaces.emplace_back(surface.surface, registerShader(surface.shader));
  return addSkin(std::move(skin));
}

class ShaderRegistry;

/// The shader of each surface of an MD3 entity, as the stock renderer picks it: the entity's
/// customShader, else its skin's match by surface name ("*" matches all), else the file's shader
/// number skinNum; written to `out` (one per surface, 0 = default).
void md3SurfaceShaders(const q3::Md3Model& md3, const q3abi::refEntity_t& entity, const SkinEntry* skin,
                       const ShaderRegistry& shaders, std::vector<q3abi::qhandle_t>& out);

}  // namespace glue
