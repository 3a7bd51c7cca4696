#include "port/engine_glue/shader_scripts.h"

#include <GL/gl.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>

#include "port/engine_glue/engine.h"

namespace glue {
namespace {

/// Splits script text into tokens: skips // and /* */ comments, keeps quoted strings whole,
/// treats braces as tokens, and records whether a token starts a new line.
class Lexer {
 public:
  explicit Lexer(std::string_view text) : text_(text) {}

  /// Next token ("" at the end). newLine tells if a line break preceded it.
  std::string_view next(bool& newLine) {
    newLine = false;
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') { newLine = true; ++pos_; }
      else if (c == ' ' || c == '\t' || c == '\r') ++pos_;
      else if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '*') {
        const size_t end = text_.find("*/", pos_ + 2);
        pos_ = end == std::string_view::npos ? text_.size() : end + 2;
        newLine = true;
      } else break;
    }
    if (pos_ >= text_.size()) return {};
    const size_t start = pos_;
    if (text_[pos_] == '{' || text_[pos_] == '}') return text_.substr(pos_++, 1);
    if (text_[pos_] == '"') {
      const size_t end = text_.find('"', pos_ + 1);
      const size_t stop = end == std::string_view::npos ? text_.size() : end;
      pos_ = end == std::string_view::npos ? text_.size() : end + 1;
      return text_.substr(start + 1, stop - start - 1);
    }
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_])) &&
           text_[pos_] != '{' && text_[pos_] != '}')
      ++pos_;
    return text_.substr(start, pos_ - start);
  }
  size_t position() const { return pos_; }

 private:
  std::string_view text_;
  size_t pos_ = 0;
};

unsigned blendFactor(std::string_view word) {
  const std::string w = normalizeName(word);
  if (w == "gl_one") return GL_ONE;
  if (w == "gl_zero") return GL_ZERO;
  if (w == "gl_src_color") return GL_SRC_COLOR;
  if (w == "gl_one_minus_src_color") return GL_ONE_MINUS_SRC_COLOR;
  if (w == "gl_dst_color") return GL_DST_COLOR;
  if (w == "gl_one_minus_dst_color") return GL_ONE_MINUS_DST_COLOR;
  if (w == "gl_src_alpha") return GL_SRC_ALPHA;
  if (w == "gl_one_minus_src_alpha") return GL_ONE_MINUS_SRC_ALPHA;
  if (w == "gl_dst_alpha") return GL_DST_ALPHA;
  if (w == "gl_one_minus_dst_alpha") return GL_ONE_MINUS_DST_ALPHA;
  if (w == "gl_src_alpha_saturate") return GL_SRC_ALPHA_SATURATE;
  return GL_ONE;
}

/// One stage as read from the script.
struct StageWords {
  std::vector<std::string> images;
  float animFrequency = 0;
  bool clamp = false, lightmap = false, hasBlend = false;
  BlendFunc blend;
  AlphaTest alphaTest = AlphaTest::None;
  bool vertexColor = false, vertexAlpha = false;
};

}  // namespace

ShaderLook parseShaderBody(std::string_view body) {
  ShaderLook look;
  look.fromScript = true;
  Lexer lexer(body);
  bool newLine = false;
  int depth = 0;
  std::vector<StageWords> stages;
  std::string_view token;
  // Reads the rest of the current line's tokens.
  auto restOfLine = [&](std::vector<std::string>& out) {
    for (;;) {
      Lexer ahead = lexer;
      bool nl = false;
      const std::string_view t = ahead.next(nl);
      if (t.empty() || nl || t == "{" || t == "}") return;
      out.emplace_back(t);
      lexer = ahead;
    }
  };
  while (!(token = lexer.next(newLine)).empty()) {
    if (token == "{") {
      if (++depth == 2) stages.emplace_back();
      continue;
    }
    if (token == "}") {
      if (--depth <= 0) break;
      continue;
    }
    const std::string word = normalizeName(token);
    std::vector<std::string> args;
    restOfLine(args);
    if (depth == 1) {
      if (word == "surfaceparm" && !args.empty()) {
        const std::string parm = normalizeName(args[0]);
        if (parm == "sky") look.sky = true;
        else if (parm == "nodraw") look.nodraw = true;
        else if (parm == "trans") look.translucent = true;
      } else if (word == "q3map_surfacelight" && !args.empty()) {
        look.surfaceLight = std::strtof(args[0].c_str(), nullptr);
      }
    } else if (depth == 2 && !stages.empty()) {
      StageWords& stage = stages.back();
      if ((word == "map" || word == "clampmap") && !args.empty()) {
        if (normalizeName(args[0]) == "$lightmap") stage.lightmap = true;
        else stage.images = {args[0]};
        stage.clamp = word == "clampmap";
      } else if (word == "animmap" && args.size() >= 2) {
        stage.animFrequency = std::strtof(args[0].c_str(), nullptr);
        stage.images.assign(args.begin() + 1, args.end());
      } else if (word == "blendfunc" && !args.empty()) {
        stage.hasBlend = true;
        const std::string mode = normalizeName(args[0]);
        if (mode == "add") stage.blend = {GL_ONE, GL_ONE};
        else if (mode == "filter") stage.blend = {GL_DST_COLOR, GL_ZERO};
        else if (mode == "blend") stage.blend = {GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA};
        else if (args.size() >= 2) stage.blend = {blendFactor(args[0]), blendFactor(args[1])};
      } else if (word == "alphafunc" && !args.empty()) {
        const std::string func = normalizeName(args[0]);
        stage.alphaTest = func == "gt0" ? AlphaTest::Gt0 : func == "lt128" ? AlphaTest::Lt128
                                                                         : AlphaTest::Ge128;
      } else if (word == "rgbgen" && !args.empty()) {
        const std::string gen = normalizeName(args[0]);
        stage.vertexColor = gen == "vertex" || gen == "exactvertex" || gen == "lightingdiffuse";
      } else if (word == "alphagen" && !args.empty()) {
        stage.vertexAlpha = normalizeName(args[0]) == "vertex";
      }
    }
  }
  // The first stage that shows a texture (not the lightmap) is the look.
  for (const StageWords& stage : stages) {
    if (stage.lightmap) continue;
    look.images = stage.images;
    look.animFrequency = stage.animFrequency;
    look.clamp = stage.clamp;
    look.blend = stage.blend;
    look.alphaTest = stage.alphaTest;
    look.vertexColor = stage.vertexColor;
    look.vertexAlpha = stage.vertexAlpha;
    return look;
  }
  if (stages.empty() && !look.sky) look.nodraw = true;
  return look;
}

void ShaderScripts::addScript(std::string_view text) {
  Lexer lexer(text);
  bool newLine = false;
  for (;;) {
    std::string_view name = lexer.next(newLine);
    if (name.empty()) return;
    if (name == "{" || name == "}") continue;  // stray brace: resynchronise on the next name
    const size_t nameEnd = lexer.position();
    std::string_view open = lexer.next(newLine);
    if (open != "{") continue;
    int depth = 1;
    std::string_view token;
    while (depth > 0 && !(token = lexer.next(newLine)).empty()) {
      if (token == "{") ++depth;
      else if (token == "}") --depth;
    }
    const size_t bodyStart = text.find('{', nameEnd);
    const std::string_view body = text.substr(bodyStart, lexer.position() - bodyStart);
    bodies_.try_emplace(normalizeName(name), body);
    if (token.empty()) return;  // unterminated last shader: keep what we have
  }
}

void ShaderScripts::load(const Engine& engine) {
  bodies_.clear();
  // The engine concatenates the alphabetically sorted scripts in reverse, so the definition in
  // the alphabetically last script wins: feed them last-first to our first-wins index.
  std::vector<std::string> files = engine.listFiles("scripts", ".shader");
  std::sort(files.begin(), files.end(), [](const std::string& a, const std::string& b) {
    return normalizeName(a) < normalizeName(b);
  });
  std::reverse(files.begin(), files.end());
  for (const std::string& file : files) {
    const auto bytes = engine.readFile("scripts/" + file);
    if (!bytes) continue;
    addScript(std::string_view(reinterpret_cast<const char*>(bytes->data()), bytes->size()));
  }
}

std::optional<ShaderLook> ShaderScripts::find(std::string_view name) const {
  const auto found = bodies_.find(normalizeName(stripExtension(name)));
  if (found == bodies_.end()) {
    const auto exact = bodies_.find(normalizeName(name));
    if (exact == bodies_.end()) return std::nullopt;
    return parseShaderBody(exact->second);
  }
  return parseShaderBody(found->second);
}

}  // namespace glue
