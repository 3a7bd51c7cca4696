#include "port/engine_glue/models.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>

#include "port/engine_glue/engine.h"
#include "port/q3formats/common/byte_reader.h"
#include "port/q3formats/common/format_error.h"

namespace glue {
namespace {

constexpr size_t kMd3HeaderSize = 108;
constexpr size_t kMd3FrameSize = 56;
constexpr size_t kMd3TagSize = 112;
constexpr size_t kMd3SurfaceHeaderSize = 108;
constexpr size_t kMd3ShaderSize = 68;
constexpr int kMaxMd3Frames = 1024, kMaxMd3Tags = 16, kMaxMd3Surfaces = 32, kMaxMd3Shaders = 256;
constexpr size_t kMaxModels = 1024;   // stock MAX_MOD_KNOWN
constexpr size_t kMaxSkins = 1024;

glm::vec3 readVec3(const q3::ByteReader& reader, size_t offset, const char* field) {
  return {reader.read<float>(offset, field), reader.read<float>(offset + 4, field),
          reader.read<float>(offset + 8, field)};
}

}  // namespace

Md3Info readMd3Info(const std::vector<uint8_t>& bytes, const std::string& file) {
  const q3::ByteReader reader(std::as_bytes(std::span(bytes)), file);
  reader.require(0, 1, kMd3HeaderSize, "header");
  if (reader.fixedString(0, 4, "ident") != "IDP3") reader.fail("ident", "not an MD3 (IDP3)");
  if (reader.read<int32_t>(4, "version") != 15) reader.fail("version", "expected 15");
  const int32_t numFrames = reader.read<int32_t>(76, "numFrames");
  const int32_t numTags = reader.read<int32_t>(80, "numTags");
  const int32_t numSurfaces = reader.read<int32_t>(84, "numSurfaces");
  const int32_t ofsFrames = reader.read<int32_t>(92, "ofsFrames");
  const int32_t ofsTags = reader.read<int32_t>(96, "ofsTags");
  const int32_t ofsSurfaces = reader.read<int32_t>(100, "ofsSurfaces");
  if (numFrames < 1 || numFrames > kMaxMd3Frames) reader.fail("numFrames", "out of range");
  if (numTags < 0 || numTags > kMaxMd3Tags) reader.fail("numTags", "out of range");
  if (numSurfaces < 0 || numSurfaces > kMaxMd3Surfaces) reader.fail("numSurfaces", "out of range");
  if (ofsFrames < 0 || ofsTags < 0 || ofsSurfaces < 0) reader.fail("offsets", "negative");

  Md3Info info;
  reader.require(size_t(ofsFrames), size_t(numFrames), kMd3FrameSize, "frames");
  for (int f = 0; f < numFrames; ++f) {
    const size_t at = size_t(ofsFrames) + size_t(f) * kMd3FrameSize;
    info.frames.push_back({readVec3(reader, at, "frame mins"), readVec3(reader, at + 12, "frame maxs")});
  }
  info.tagsPerFrame = numTags;
  reader.require(size_t(ofsTags), size_t(numFrames) * size_t(numTags), kMd3TagSize, "tags");
  for (int t = 0; t < numFrames * numTags; ++t) {
    const size_t at = size_t(ofsTags) + size_t(t) * kMd3TagSize;
    Md3Tag tag;
    tag.name = normalizeName(reader.fixedString(at, 64, "tag name"));
    tag.origin = readVec3(reader, at + 64, "tag origin");
    for (int a = 0; a < 3; ++a) tag.axis[a] = readVec3(reader, at + 76 + 12 * a, "tag axis");
    info.tags.push_back(std::move(tag));
  }
  size_t surfaceAt = size_t(ofsSurfaces);
  for (int s = 0; s < numSurfaces; ++s) {
    reader.require(surfaceAt, 1, kMd3SurfaceHeaderSize, "surface header");
    if (reader.fixedString(surfaceAt, 4, "surface ident") != "IDP3")
      reader.fail("surface ident", "surface " + std::to_string(s) + " is not IDP3");
    info.surfaceNames.push_back(normalizeName(reader.fixedString(surfaceAt + 4, 64, "surface name")));
    const int32_t numShaders = reader.read<int32_t>(surfaceAt + 76, "surface numShaders");
    const int32_t ofsShaders = reader.read<int32_t>(surfaceAt + 92, "surface ofsShaders");
    const int32_t ofsEnd = reader.read<int32_t>(surfaceAt + 104, "surface ofsEnd");
    if (numShaders < 0 || numShaders > kMaxMd3Shaders || ofsShaders < 0)
      reader.fail("surface shaders", "out of range");
    std::vector<std::string> shaders;
    for (int i = 0; i < numShaders; ++i)
      shaders.push_back(reader.fixedString(surfaceAt + size_t(ofsShaders) + size_t(i) * kMd3ShaderSize,
                                           64, "surface shader name"));
    info.surfaceShaders.push_back(std::move(shaders));
    if (ofsEnd <= 0) reader.fail("surface ofsEnd", "not positive");
    surfaceAt += size_t(ofsEnd);
  }
  return info;
}

std::vector<std::pair<std::string, std::string>> parseSkin(std::string_view text) {
  std::vector<std::pair<std::string, std::string>> pairs;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find_first_of("\r\n", start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    const size_t comma = line.find(',');
    if (comma == std::string_view::npos) continue;
    auto trim = [](std::string_view s) {
      while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '"')) s.remove_prefix(1);
      while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '"')) s.remove_suffix(1);
      return s;
    };
    const std::string surface = normalizeName(trim(line.substr(0, comma)));
    const std::string_view shader = trim(line.substr(comma + 1));
    if (surface.empty() || surface.rfind("tag_", 0) == 0 || shader.empty()) continue;
    pairs.emplace_back(surface, std::string(shader));
  }
  return pairs;
}

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
    const std::string base = stripExtension(key);
    for (int lod = 0; lod < 3; ++lod) {
      const std::string file = lod == 0 ? key : base + "_" + std::to_string(lod) + ".md3";
      auto bytes = engine.readFile(file);
      if (!bytes) {
        if (lod == 0) break;
        continue;
      }
      try {
        auto info = std::make_shared<const Md3Info>(readMd3Info(*bytes, file));
        entry.lods.push_back(std::move(info));
        entry.lodBytes.push_back(std::make_shared<const std::vector<uint8_t>>(std::move(*bytes)));
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
  const Md3Info& info = *entry->lods[0];
  const int frames = static_cast<int>(info.frames.size());
  const std::string wanted = normalizeName(tagName);
  auto find = [&](int frame) -> const Md3Tag* {
    frame = std::clamp(frame, 0, frames - 1);   // the stock renderer clamps too
    for (int t = 0; t < info.tagsPerFrame; ++t) {
      const Md3Tag& tag = info.tags[size_t(frame) * info.tagsPerFrame + t];
      if (tag.name == wanted) return &tag;
    }
    return nullptr;
  };
  const Md3Tag* start = find(startFrame);
  const Md3Tag* end = find(endFrame);
  if (start == nullptr || end == nullptr) return false;
  if (!std::isfinite(frac)) frac = 0.0f;
  const float back = 1.0f - frac;
  const glm::vec3 origin = start->origin * back + end->origin * frac;
  for (int i = 0; i < 3; ++i) out.origin[i] = origin[i];
  for (int a = 0; a < 3; ++a) {
    glm::vec3 axis = start->axis[a] * back + end->axis[a] * frac;
    const float length = glm::length(axis);
    if (length > 1e-6f) axis /= length;
    for (int i = 0; i < 3; ++i) out.axis[a][i] = axis[i];
  }
  return true;
}

bool ModelRegistry::md3Bounds(q3abi::qhandle_t handle, glm::vec3& mins, glm::vec3& maxs) const {
  const ModelEntry* entry = model(handle);
  if (entry == nullptr || entry->kind != ModelKind::Md3 || entry->lods.empty()) return false;
  mins = entry->lods[0]->frames[0].mins;
  maxs = entry->lods[0]->frames[0].maxs;
  return true;
}

}  // namespace glue
