// shader_scan [GAME_DIR] [SHADER_NAME...]: parses every scripts/*.shader of a game folder the way
// the engine orders them and reports unknown keywords (target: none), other warnings, ignored
// scripts and totals. With shader names, prints how each one reads as a neutral material.
#include <cstdio>
#include <map>
#include <string>

#include "port/q3formats/shader/material.h"
#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/vfs/game_filesystem.h"

namespace {

const char* alphaModeName(q3::AlphaMode m) {
  switch (m) {
    case q3::AlphaMode::Opaque: return "opaque";
    case q3::AlphaMode::Mask: return "mask";
    case q3::AlphaMode::Blend: return "blend";
    case q3::AlphaMode::Additive: return "additive";
    case q3::AlphaMode::Multiply: return "multiply";
  }
  return "?";
}

const char* lightingName(q3::LightingMode m) {
  switch (m) {
    case q3::LightingMode::Lightmap: return "lightmap";
    case q3::LightingMode::Vertex: return "vertex";
    case q3::LightingMode::Diffuse: return "diffuse (light grid)";
    case q3::LightingMode::Unlit: return "unlit";
  }
  return "?";
}

void printMaterial(const q3::ShaderDef& def) {
  const q3::MaterialInfo m = q3::deriveMaterial(def);
  std::printf("%s  (%s:%d%s)\n", def.name.c_str(), def.file.c_str(), def.line, def.implicit ? ", implicit" : "");
  std::printf("  stages %zu, base '%s'%s, alpha %s", def.stages.size(), m.baseTexture.c_str(),
              m.animFrames.empty() ? "" : " (animated)", alphaModeName(m.alphaMode));
  if (m.alphaMode == q3::AlphaMode::Mask) std::printf(" cutoff %.2f%s", m.alphaCutoff, m.alphaInvert ? " inverted" : "");
  std::printf(", lighting %s\n", lightingName(m.lighting));
  if (m.emissive)
    std::printf("  emissive: surfacelight %g, light image '%s', glow stages %zu\n", m.surfaceLight,
                m.lightImage.c_str(), m.glowTextures.size());
  if (m.sky) std::printf("  sky, far box '%s'\n", m.skyBox.farFaces[0].c_str());
  if (m.environmentMapped) std::printf("  environment map '%s'\n", m.environmentTexture.c_str());
  if (!m.coverTexture.empty())
    std::printf("  cover '%s'%s\n", m.coverTexture.c_str(), m.coverVertexAlpha ? " by vertex alpha" : "");
  std::printf("  %s%s%s%s%s%s\n", m.twoSided ? "two-sided " : "", m.portal ? "portal " : "", m.invisible ? "invisible " : "",
              m.fogVolume ? "fog " : "", m.liquid ? "liquid " : "", m.uvAnimation.empty() ? "" : "uv-animated");
}

}  // namespace

int main(int argc, char** argv) {
  const std::string gameDir = argc > 1 ? argv[1] : "/usr/share/games/openarena/baseoa";
  try {
    q3::GameFileSystem fs(gameDir);
    q3::ShaderLibrary library;
    const auto scripts = fs.listFiles("scripts", ".shader");
    library.addScriptsInEngineOrder(scripts, [&](const std::string& f) { return fs.readFile(f); });
    const size_t definitions = library.size() + library.shadowedDefinitions();
    if (argc > 2) {
      for (int i = 2; i < argc; ++i) {
        auto def = library.resolve(argv[i], q3::ImplicitLighting::Lightmap,
                                   [&](const std::string& f) { return fs.exists(f); });
        if (def) printMaterial(*def);
        else std::printf("%s: no script and no image (the engine's default shader)\n", argv[i]);
      }
      return 0;
    }
    std::map<std::string, int> unknown;
    size_t otherWarnings = 0;
    for (const auto& w : library.warnings()) {
      if (w.unknownKeyword) {
        unknown[w.keyword] += w.count;
        std::printf("unknown: %s:%d '%s' (x%d)\n", w.file.c_str(), w.line, w.keyword.c_str(), w.count);
      } else {
        ++otherWarnings;
        std::printf("warning: %s:%d shader '%s': %s: %s\n", w.file.c_str(), w.line, w.shader.c_str(),
                    w.keyword.c_str(), w.message.c_str());
      }
    }
    for (const auto& e : library.errors()) std::printf("ignored script: %s\n", e.c_str());
    std::map<std::string, int> modes;
    for (const auto& def : library.shaders()) ++modes[alphaModeName(q3::deriveMaterial(def).alphaMode)];
    std::printf("scripts %zu, definitions %zu, distinct shaders %zu, shadowed %zu\n", scripts.size(),
                definitions, library.size(), library.shadowedDefinitions());
    std::printf("materials:");
    for (const auto& [mode, n] : modes) std::printf(" %s %d", mode.c_str(), n);
    std::printf("\nunknown keywords %zu (distinct), other warnings %zu, ignored scripts %zu\n", unknown.size(),
                otherWarnings, library.errors().size());
    return unknown.empty() && library.errors().empty() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shader_scan: %s\n", e.what());
    return 2;
  }
}
