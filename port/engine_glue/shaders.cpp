#include "port/engine_glue/shaders.h"

#include <GL/gl.h>

#include <algorithm>
#include <cmath>

#include "port/engine_glue/engine.h"

#ifndef GL_CLAMP_TO_EDGE
#define GL_CLAMP_TO_EDGE 0x812F
#endif

namespace glue {
namespace {

constexpr size_t kMaxShaders = 16384;   // the stock renderer's MAX_SHADERS

/// Uploads an image as a linear-filtered GL texture (repeat or clamp-to-edge).
unsigned uploadTexture(const Image& image, bool clamp) {
  GLuint texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  const GLint wrap = clamp ? GL_CLAMP_TO_EDGE : GL_REPEAT;
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, image.width, image.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
               image.rgba.data());
  return texture;
}

/// The animMap frame shown at `seconds` among `count` frames.
size_t animFrame(size_t count, float frequency, double seconds) {
  if (count <= 1 || frequency <= 0.0f) return 0;
  const double index = std::floor(seconds * frequency);
  return static_cast<size_t>(std::fmod(std::max(index, 0.0), double(count)));
}

void deleteTextures(std::vector<unsigned>& textures) {
  if (!textures.empty()) glDeleteTextures(static_cast<GLsizei>(textures.size()), textures.data());
  textures.clear();
}

ShaderEntry makeDefaultEntry() {
  ShaderEntry entry;
  entry.name = "<default>";
  entry.frames = {defaultImage()};
  entry.isDefault = true;
  return entry;
}

}  // namespace

ShaderRegistry::ShaderRegistry() { entries_.push_back(makeDefaultEntry()); }

ShaderRegistry::LookupKey::LookupKey(std::string_view name) {
  // normalizeName(stripExtension(name)), on the stack: registered names are shorter than kMaxQPath.
  if (name.size() >= sizeof(text)) return;   // never registered: an empty key finds nothing
  const size_t dot = name.find_last_of('.');
  const size_t slash = name.find_last_of('/');
  length = dot != std::string_view::npos && (slash == std::string_view::npos || dot > slash) ? dot : name.size();
  for (size_t i = 0; i < length; ++i) {
    const char c = name[i];
    text[i] = c == '\\' ? '/' : (c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c);
  }
}

q3abi::qhandle_t ShaderRegistry::find(std::string_view name) const {
  if (name.empty()) return 0;
  const LookupKey key(name);
  const auto found = byName_.find(key.view());
  return found == byName_.end() ? 0 : found->second;
}

q3abi::qhandle_t ShaderRegistry::registerShader(const Engine& engine, const ShaderScripts& scripts,
                                                ImageCache& images, std::string_view requested,
                                                bool mipmaps) {
  if (requested.empty() || requested.size() >= q3abi::kMaxQPath) {
    engine.warn("RegisterShader: bad name '" + std::string(requested) + "'");
    return 0;
  }
  // Games register some shaders every frame: a known name is found without making strings.
  const LookupKey lookup(requested);
  if (const auto known = byName_.find(lookup.view()); known != byName_.end()) return known->second;
  const std::string name(requested);
  const std::string key(lookup.view());
  if (entries_.size() >= kMaxShaders) {
    engine.warn("RegisterShader: too many shaders, '" + name + "' uses the default");
    return 0;
  }

  ShaderEntry entry;
  entry.name = key;
  entry.clampToEdge = !mipmaps;
  if (auto look = scripts.find(name)) {
    entry.look = std::move(*look);
  } else {
    // Implicit shader: the image of that name, alpha-blended and tinted by SetColor in 2D.
    entry.look.images = {name};
    entry.look.blend = {GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA};
    entry.look.vertexColor = entry.look.vertexAlpha = true;
  }
  entry.clampToEdge = entry.clampToEdge || entry.look.clamp;
  for (const std::string& imageName : entry.look.images) {
    auto image = images.load(engine, imageName);
    if (!image && !entry.look.fromScript) {
      // Like the stock renderer: a developer message, the default shader (handle 0) returned.
      engine.print(q3abi::PRINT_DEVELOPER, "pathtracer: couldn't find image for shader %s\n",
                   name.c_str());
      byName_.emplace(key, 0);
      return 0;
    }
    if (!image) engine.warn("shader " + name + ": missing image " + imageName);
    entry.frames.push_back(image ? image : defaultImage());
  }
  if (entry.frames.empty()) entry.frames.push_back(whiteImage());
  for (const ShaderLook& layer : entry.look.layers) {
    std::vector<std::shared_ptr<const Image>> frames;
    for (const std::string& imageName : layer.images) {
      auto image = images.load(engine, imageName);
      frames.push_back(image ? image : defaultImage());
    }
    if (frames.empty()) frames.push_back(whiteImage());
    entry.layerFrames.push_back(std::move(frames));
  }
  if (entry.look.shine) {
    entry.shineImage = images.load(engine, entry.look.shine->image);
    if (!entry.shineImage) engine.warn("shader " + name + ": missing image " + entry.look.shine->image);
  }
  // Every stage's textures for drawing the whole script in 2D, filled on its first 2D draw.
  for (const q3::ShaderStage& stage : entry.look.stages)
    entry.stageTextures.push_back(StageTextures{{}, entry.clampToEdge || stage.clamp});

  const auto handle = static_cast<q3abi::qhandle_t>(entries_.size());
  entries_.push_back(std::move(entry));
  byName_.emplace(key, handle);
  return handle;
}

ShaderEntry* ShaderRegistry::entry(q3abi::qhandle_t handle) {
  if (handle < 0 || static_cast<size_t>(handle) >= entries_.size()) return nullptr;
  return &entries_[static_cast<size_t>(handle)];
}

size_t ShaderRegistry::resolveIndex(q3abi::qhandle_t handle) const {
  if (handle < 0 || static_cast<size_t>(handle) >= entries_.size()) return 0;
  const q3abi::qhandle_t target = entries_[static_cast<size_t>(handle)].remappedTo;
  if (target > 0 && static_cast<size_t>(target) < entries_.size())
    return static_cast<size_t>(target);
  return static_cast<size_t>(handle);
}

const ShaderEntry& ShaderRegistry::resolve(q3abi::qhandle_t handle) const {
  return entries_[resolveIndex(handle)];
}

void ShaderRegistry::remap(const Engine& engine, const ShaderScripts& scripts, ImageCache& images,
                           const std::string& oldName, const std::string& newName,
                           float timeOffset) {
  q3abi::qhandle_t oldHandle = find(oldName);
  if (oldHandle == 0) oldHandle = registerShader(engine, scripts, images, oldName, true);
  const q3abi::qhandle_t newHandle = registerShader(engine, scripts, images, newName, true);
  if (oldHandle == 0) {
    engine.warn("RemapShader: shader " + oldName + " not found");
    return;
  }
  ShaderEntry& target = entries_[static_cast<size_t>(oldHandle)];
  // Remapping a shader to itself restores it.
  target.remappedTo = newHandle == oldHandle ? 0 : newHandle;
  target.remapTimeOffset = timeOffset;
}

unsigned ShaderRegistry::glTexture(q3abi::qhandle_t handle, double seconds) {
  ShaderEntry& entry = entries_[resolveIndex(handle)];
  if (entry.glTextures.empty())
    for (const auto& image : entry.frames) entry.glTextures.push_back(uploadTexture(*image, entry.clampToEdge));
  return entry.glTextures[animFrame(entry.glTextures.size(), entry.look.animFrequency, seconds)];
}

unsigned ShaderRegistry::stageGlTexture(const Engine& engine, const ImageSource& images, q3abi::qhandle_t handle,
                                        size_t stage, double seconds) {
  ShaderEntry& entry = entries_[resolveIndex(handle)];
  if (stage >= entry.stageTextures.size() || stage >= entry.look.stages.size()) return glTexture(handle, seconds);
  const q3::ShaderStage& script = entry.look.stages[stage];
  StageTextures& textures = entry.stageTextures[stage];
  if (textures.glTextures.empty()) {
    if (script.source == q3::TextureSource::Image) {
      for (const std::string& imageName : script.textures) {
        const auto image = images(imageName);
        if (!image) engine.warn("shader " + entry.name + ": missing image " + imageName);
        textures.glTextures.push_back(uploadTexture(image ? *image : *defaultImage(), textures.clamp));
      }
    }
    if (textures.glTextures.empty()) textures.glTextures.push_back(uploadTexture(*whiteImage(), textures.clamp));
  }
  return textures.glTextures[animFrame(textures.glTextures.size(), script.animFrequency, seconds)];
}

void ShaderRegistry::clear() {
  for (ShaderEntry& entry : entries_) {
    deleteTextures(entry.glTextures);
    for (StageTextures& textures : entry.stageTextures) deleteTextures(textures.glTextures);
  }
  entries_.clear();
  byName_.clear();
  entries_.push_back(makeDefaultEntry());
}

}  // namespace glue
