#include "port/q3formats/shader/shader_library.h"

#include <algorithm>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/common/tokenizer.h"

namespace q3 {

namespace {
/// Position of the extension dot of the last path component, or npos.
size_t extensionDot(std::string_view name) {
  const size_t dot = name.find_last_of('.');
  const size_t slash = name.find_last_of("/\\");
  if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash)) return std::string_view::npos;
  return dot;
}
}  // namespace

std::string shaderKey(std::string_view name) {
  const size_t dot = extensionDot(name);
  std::string key = toLowerAscii(name.substr(0, dot));
  std::replace(key.begin(), key.end(), '\\', '/');
  return key;
}

std::vector<std::string> imageCandidates(std::string_view name) {
  std::vector<std::string> out;
  const size_t dot = extensionDot(name);
  if (dot != std::string_view::npos) out.emplace_back(name);
  const std::string stem(name.substr(0, dot));
  for (const char* ext : {".tga", ".jpg", ".jpeg", ".png", ".bmp"}) {
    std::string candidate = stem + ext;
    if (std::find(out.begin(), out.end(), candidate) == out.end()) out.push_back(std::move(candidate));
  }
  return out;
}

ShaderDef makeImplicitShader(std::string_view name, const std::string& imagePath, ImplicitLighting lighting) {
  ShaderDef def;
  def.name = std::string(name);
  def.implicit = true;
  ShaderStage base;
  base.textures = {imagePath};
  switch (lighting) {
    case ImplicitLighting::Lightmap: {
      ShaderStage lightmap;
      lightmap.source = TextureSource::Lightmap;
      lightmap.textures = {"$lightmap"};
      lightmap.tcGen = TcGen::Lightmap;
      lightmap.rgbGen = RgbGen::IdentityLighting;
      base.hasBlend = true;
      base.srcBlend = BlendFactor::DstColor;
      base.dstBlend = BlendFactor::Zero;
      base.rgbGen = RgbGen::Identity;
      def.stages = {lightmap, base};
      return def;
    }
    case ImplicitLighting::Vertex: base.rgbGen = RgbGen::ExactVertex; break;
    case ImplicitLighting::Diffuse: base.rgbGen = RgbGen::LightingDiffuse; break;
    case ImplicitLighting::TwoD:
      base.rgbGen = RgbGen::Vertex;
      base.alphaGen = AlphaGen::Vertex;
      base.hasBlend = true;
      base.srcBlend = BlendFactor::SrcAlpha;
      base.dstBlend = BlendFactor::OneMinusSrcAlpha;
      def.cull = CullMode::TwoSided;
      break;
  }
  def.stages = {base};
  return def;
}

std::vector<std::string> scriptsInPriorityOrder(std::vector<std::string> scriptNames) {
  std::stable_sort(scriptNames.begin(), scriptNames.end(), [](const std::string& a, const std::string& b) {
    return comparePathsLikeEngine(a, b) > 0;
  });
  return scriptNames;
}

bool ShaderLibrary::addScript(std::string_view text, const std::string& file) {
  ShaderScript script;
  try {
    script = parseShaderScript(text, file);
  } catch (const FormatError& e) {
    errors_.push_back(std::string(e.what()) + " (script ignored)");
    return false;
  }
  for (auto& def : script.shaders) {
    std::string key = shaderKey(def.name);
    if (index_.contains(key)) {
      ++shadowed_;
      continue;
    }
    index_.emplace(std::move(key), shaders_.size());
    shaders_.push_back(std::move(def));
  }
  for (auto& w : script.warnings) warnings_.push_back(std::move(w));
  return true;
}

size_t ShaderLibrary::addScriptsInEngineOrder(
    std::vector<std::string> scriptNames,
    const std::function<std::optional<std::vector<std::byte>>(const std::string&)>& read) {
  size_t added = 0;
  for (const std::string& name : scriptsInPriorityOrder(std::move(scriptNames))) {
    const auto bytes = read(name);
    if (!bytes) continue;
    added += addScript({reinterpret_cast<const char*>(bytes->data()), bytes->size()}, name) ? 1 : 0;
  }
  return added;
}

const ShaderDef* ShaderLibrary::find(std::string_view name) const {
  auto it = index_.find(shaderKey(name));
  return it == index_.end() ? nullptr : &shaders_[it->second];
}

std::optional<ShaderDef> ShaderLibrary::resolve(std::string_view name, ImplicitLighting lighting,
                                                const std::function<bool(const std::string&)>& fileExists) const {
  if (const ShaderDef* def = find(name)) return *def;
  for (const std::string& candidate : imageCandidates(name))
    if (fileExists(candidate)) return makeImplicitShader(name, candidate, lighting);
  return std::nullopt;
}

}  // namespace q3
