#include "port/q3formats/model/skin.h"

#include "port/q3formats/common/tokenizer.h"

namespace q3 {

std::string Skin::shaderFor(std::string_view surface) const {
  for (const auto& s : surfaces)
    if (equalsIgnoreCase(s.surface, surface)) return s.shader;
  return "";
}

Skin parseSkin(std::string_view text, const std::string& file) {
  Skin skin;
  Tokenizer tok(text, file, {.commaSeparates = true, .maxTokenLength = 1024});
  auto warn = [&](int line, const std::string& message) {
    if (skin.warnings.size() < 64) skin.warnings.push_back(file + ":" + std::to_string(line) + ": " + message);
  };
  while (auto surface = tok.next()) {
    const int line = surface->line;
    auto shader = tok.nextOnLine();
    // Anything after the shader on the same line is not part of the format.
    if (shader && tok.nextOnLine()) {
      warn(line, "extra text after the shader name ignored");
      tok.skipRestOfLine();
    }
    const std::string name = toLowerAscii(surface->text);
    if (name.find("tag_") != std::string::npos) continue;  // tags carry no shader
    if (!shader || shader->text.empty()) {
      warn(line, "surface '" + surface->text + "' has no shader");
      continue;
    }
    if (skin.surfaces.size() >= kMaxSkinSurfaces) {
      warn(line, "more than " + std::to_string(kMaxSkinSurfaces) + " surfaces, rest ignored");
      break;
    }
    skin.surfaces.push_back({name, shader->text});
  }
  return skin;
}

}  // namespace q3
