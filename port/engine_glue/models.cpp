#include "port/engine_glue/models.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>

#include "port/engine_glue/engine.h"
#include "port/engine_glue/shaders.h"
#include "port/q3formats/common/byte_reader.h"
#include "port/q3formats/common/format_error.h"

namespace glue {
namespace {

constexpr size_t kMaxModels = 1024;   // stock MAX_MOD_KNOWN
constexpr size_t kMaxSkins = 1024;

}  // namespace

ModelRegistry::ModelRegistry() { clear(); }

void ModelRegistry::clear() {
  models_.assign(1, ModelEntry{});   // handle 0: no model
  models_[0].name = "<none>";
  modelsByName_.clear();
  skins_.assign(1, SkinEntry{});
  skinsByName_.clear();
}

q3abi::qhandle_t ModelRegistry::registerModel(const Engine& engine, const std::string& name,
                                              int worldSubmodelCount) {
  if (name.empty() || name.size() >= q3abi::kMaxQPath) {
    engine.warn("RegisterModel: bad name '" + name + "'");
    return 0;
  }
  const std::string key = normalizeName(name);
  if (const auto found = modelsByName_.find(key); found != modelsByName_.end()) return found->second;
  if (models_.size() >= kMaxModels) {
    engine.warn("RegisterModel: too many models, " + name + " dropped");
    return 0;
  }
  ModelEntry entry;
  entry.name = key;
  if (key[0] == '*') {
    char* end = nullptr;
    const long index = std::strtol(key.c_str() + 1, &end, 10);
    if (end == key.c_str() + 1 || *end != '\0' || index < 1 || index >= worldSubmodelCount) {
      engine.warn("RegisterModel: no brush model " + name + " in this map");
      modelsByName_.emplace(key, 0);
      return 0;
    }
    entry.kind = ModelKind::Brush;
    entry.brushIndex = static_cast<int>(index);
  } else {
    for (int lod = 0; lod < 3; ++lod) {
      const std::string file = q3::md3LodName(key, lod);
      auto bytes = engine.readFile(file);
      if (!bytes) {
        if (lod == 0) break;
        continue;
      }
      try {
        entry.lods.push_back(std::make_shared<const q3::Md3Model>(
            q3::parseMd3(std::as_bytes(std::span(*bytes)), file)));
      } catch (const q3::FormatError& error) {
        engine.warn(std::string("RegisterModel: ") + error.what());
        if (lod == 0) break;
      }
    }
    if (entry.lods.empty()) {
      engine.print(q3abi::PRINT_DEVELOPER, "RegisterModel: couldn't load %s\n", name.c_str());
      modelsByName_.emplace(key, 0);
      return 0;
    }
    entry.kind = ModelKind::Md3;
  }
  const auto handle = static_cast<q3abi::qhandle_t>(models_.size());
  models_.push_back(std::move(entry));
  modelsByName_.emplace(key, handle);
  return handle;
}

const ModelEntry* ModelRegistry::model(q3abi::qhandle_t handle) const {
  if (handle <= 0 || static_cast<size_t>(handle) >= models_.size()) return nullptr;
  return &models_[static_cast<size_t>(handle)];
}

q3abi::qhandle_t ModelRegistry::addSkin(SkinEntry skin) {
  if (skins_.size() >= kMaxSkins) return 0;
  const auto handle = static_cast<q3abi::qhandle_t>(skins_.size());
  skinsByName_.emplace(skin.name, handle);
  skins_.push_back(std::move(skin));
  return handle;
}

const SkinEntry* ModelRegistry::skin(q3abi::qhandle_t handle) const {
  if (handle <= 0 || static_cast<size_t>(handle) >= skins_.size()) return nullptr;
  return &skins_[static_cast<size_t>(handle)];
}

bool ModelRegistry::lerpTag(q3abi::orientation_t& out, q3abi::qhandle_t handle, int startFrame,
                            int endFrame, float frac, const std::string& tagName) const {
  std::memset(&out, 0, sizeof out);
  out.axis[0][0] = out.axis[1][1] = out.axis[2][2] = 1.0f;
  const ModelEntry* entry = model(handle);
  if (entry == nullptr || entry->kind != ModelKind::Md3 || entry->lods.empty()) return false;
  if (!std::isfinite(frac)) frac = 0.0f;
  const auto tag = q3::lerpTag(*entry->lods[0], startFrame, endFrame, frac, tagName);
  if (!tag) return false;
  for (int i = 0; i < 3; ++i) out.origin[i] = tag->origin[i];
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < 3; ++i) out.axis[a][i] = tag->axis[a][i];
  return true;
}

bool ModelRegistry::md3Bounds(q3abi::qhandle_t handle, glm::vec3& mins, glm::vec3& maxs) const {
  const ModelEntry* entry = model(handle);
  if (entry == nullptr || entry->kind != ModelKind::Md3 || entry->lods.empty()) return false;
  const q3::Md3Frame& frame = entry->lods[0]->frames.at(0);   // parseMd3 requires >= 1 frame
  mins = {frame.mins[0], frame.mins[1], frame.mins[2]};
  maxs = {frame.maxs[0], frame.maxs[1], frame.maxs[2]};
  return true;
}

void md3SurfaceShaders(const q3::Md3Model& md3, const q3abi::refEntity_t& entity, const SkinEntry* skin,
                       const ShaderRegistry& shaders, std::vector<q3abi::qhandle_t>& out) {
  out.clear();
  for (const q3::Md3Surface& surface : md3.surfaces) {
    q3abi::qhandle_t shader = entity.customShader;
    if (shader == 0 && skin != nullptr) {
      for (const auto& [name, handle] : skin->surfaces)
        if (name == "*" || name == normalizeName(surface.name)) {
          shader = handle;
          break;
        }
    } else if (shader == 0 && !surface.shaders.empty()) {
      const size_t pick = static_cast<size_t>(std::max(entity.skinNum, 0)) % surface.shaders.size();
      shader = shaders.find(surface.shaders[pick].name);
    }
    out.push_back(shader);
  }
}

}  // namespace glue
