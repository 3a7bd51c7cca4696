#include "port/q3formats/shader/shader_parser.h"
#include "port/q3formats/shader/shader_time.h"

#include <charconv>
#include <cmath>
#include <map>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/common/tokenizer.h"

namespace q3 {
namespace {

std::optional<float> parseNumber(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  float value = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end == text.data() || !std::isfinite(value)) return std::nullopt;
  return value;  // like atof, trailing garbage ("1.0f") is ignored
}

/// True for the name q3map2 gives a lightmap it writes beside the map: "maps/<map>/lm_NNNN"
/// (four or more digits, any image extension).
bool isExternalLightmapName(std::string_view path) {
  std::string lower = toLowerAscii(std::string(path));
  if (!lower.starts_with("maps/")) return false;
  const size_t slash = lower.rfind('/');
  std::string_view file = std::string_view(lower).substr(slash + 1);
  if (const size_t dot = file.rfind('.'); dot != std::string_view::npos) file = file.substr(0, dot);
  if (!file.starts_with("lm_") || file.size() < 7) return false;
  for (char c : file.substr(3))
    if (c < '0' || c > '9') return false;
  return slash > 5;   // a folder named after the map between "maps/" and the file
}

/// q3map2 writes lightmaps that are not the game's 128x128 pages beside the map and names them
/// in place of `$lightmap` ("map maps/<map>/lm_0000" + "tcGen lightmap"): such a stage is the
/// lightmap stage, drawn from its own image.
void markExternalLightmap(ShaderStage& s) {
  if (s.source != TextureSource::Image || s.textures.size() != 1 || s.animFrequency > 0) return;
  if (s.tcGen == TcGen::Lightmap || isExternalLightmapName(s.textures.front())) {
    s.source = TextureSource::Lightmap;
    s.tcGen = TcGen::Lightmap;
  }
}

struct NamedParm {
  const char* name;
  SurfaceParm bit;
};
constexpr NamedParm kSurfaceParms[] = {
    {"water", SurfaceParm::Water}, {"slime", SurfaceParm::Slime}, {"lava", SurfaceParm::Lava},
    {"playerclip", SurfaceParm::PlayerClip}, {"monsterclip", SurfaceParm::MonsterClip},
    {"nodrop", SurfaceParm::NoDrop}, {"nonsolid", SurfaceParm::NonSolid},
    {"origin", SurfaceParm::Origin}, {"trans", SurfaceParm::Trans}, {"detail", SurfaceParm::Detail},
    {"structural", SurfaceParm::Structural}, {"areaportal", SurfaceParm::AreaPortal},
    {"clusterportal", SurfaceParm::ClusterPortal}, {"donotenter", SurfaceParm::DoNotEnter},
    {"fog", SurfaceParm::Fog}, {"sky", SurfaceParm::Sky}, {"lightfilter", SurfaceParm::LightFilter},
    {"alphashadow", SurfaceParm::AlphaShadow}, {"hint", SurfaceParm::Hint},
    {"slick", SurfaceParm::Slick}, {"noimpact", SurfaceParm::NoImpact},
    {"nomarks", SurfaceParm::NoMarks}, {"ladder", SurfaceParm::Ladder},
    {"nodamage", SurfaceParm::NoDamage}, {"metalsteps", SurfaceParm::MetalSteps},
    {"flesh", SurfaceParm::Flesh}, {"nosteps", SurfaceParm::NoSteps},
    {"nodraw", SurfaceParm::NoDraw}, {"pointlight", SurfaceParm::PointLight},
    {"nolightmap", SurfaceParm::NoLightmap}, {"nodlight", SurfaceParm::NoDlight},
    {"dust", SurfaceParm::Dust}, {"botclip", SurfaceParm::BotClip},
    {"antiportal", SurfaceParm::AntiPortal}, {"lightgrid", SurfaceParm::LightGrid},
    {"skip", SurfaceParm::Skip}, {"nobotclip", SurfaceParm::NoBotClip}, {"ice", SurfaceParm::Ice},
};

std::optional<BlendFactor> blendFactorFromName(std::string_view name) {
  static const std::pair<const char*, BlendFactor> kFactors[] = {
      {"gl_zero", BlendFactor::Zero}, {"gl_one", BlendFactor::One},
      {"gl_src_color", BlendFactor::SrcColor}, {"gl_one_minus_src_color", BlendFactor::OneMinusSrcColor},
      {"gl_dst_color", BlendFactor::DstColor}, {"gl_one_minus_dst_color", BlendFactor::OneMinusDstColor},
      {"gl_src_alpha", BlendFactor::SrcAlpha}, {"gl_one_minus_src_alpha", BlendFactor::OneMinusSrcAlpha},
      {"gl_dst_alpha", BlendFactor::DstAlpha}, {"gl_one_minus_dst_alpha", BlendFactor::OneMinusDstAlpha},
      {"gl_src_alpha_saturate", BlendFactor::SrcAlphaSaturate},
  };
  for (const auto& [n, f] : kFactors)
    if (equalsIgnoreCase(name, n)) return f;
  return std::nullopt;
}

std::optional<WaveFunc> waveFuncFromName(std::string_view name) {
  static const std::pair<const char*, WaveFunc> kFuncs[] = {
      {"sin", WaveFunc::Sin}, {"triangle", WaveFunc::Triangle}, {"square", WaveFunc::Square},
      {"sawtooth", WaveFunc::Sawtooth}, {"inversesawtooth", WaveFunc::InverseSawtooth},
      {"noise", WaveFunc::Noise},
  };
  for (const auto& [n, f] : kFuncs)
    if (equalsIgnoreCase(name, n)) return f;
  return std::nullopt;
}

/// Parses one script; holds the tokenizer, the current shader and the warning list.
class ScriptParser {
 public:
  ScriptParser(std::string_view text, const std::string& file) : tok_(text, file), file_(file) {}

  ShaderScript run() {
    ShaderScript out;
    while (auto name = tok_.next()) {
      auto open = tok_.next();
      if (!open || open->quoted || open->text != "{")
        throw FormatError(file_, "shader '" + name->text + "' (line " + std::to_string(name->line) + ")",
                          "expected '{' after the shader name");
      ShaderDef def;
      def.name = name->text;
      def.file = file_;
      def.line = name->line;
      current_ = &def;
      parseBody(def);
      current_ = nullptr;
      out.shaders.push_back(std::move(def));
    }
    out.warnings = std::move(warnings_);
    return out;
  }

 private:
  // ---- warnings ----
  void warn(const std::string& keyword, const std::string& message, int line) {
    if (warnings_.size() >= ShaderLimits::maxWarnings) return;
    warnings_.push_back({file_, line, current_ ? current_->name : "", keyword, message, false, 1});
  }
  void unknown(const std::string& keyword, const std::string& context, int line) {
    if (current_) ++current_->unknownKeywords;
    auto it = unknownIndex_.find(keyword);
    if (it != unknownIndex_.end()) {
      ++warnings_[it->second].count;
      return;
    }
    if (warnings_.size() >= ShaderLimits::maxWarnings) return;
    unknownIndex_[keyword] = warnings_.size();
    warnings_.push_back({file_, line, current_ ? current_->name : "", keyword,
                         "unknown " + context + " '" + keyword + "'", true, 1});
  }

  // ---- argument helpers (arguments never cross a line break, as in the engine) ----
  std::optional<std::string> word() {
    const auto m = tok_.mark();
    auto t = tok_.nextOnLine();
    if (!t) return std::nullopt;
    if (!t->quoted && (t->text == "{" || t->text == "}")) {  // a brace is structure, not an argument
      tok_.reset(m);
      return std::nullopt;
    }
    return t->text;
  }
  /// Skips the remaining arguments of a line, stopping before a brace.
  void skipArgs() {
    while (word()) {
    }
  }
  float number(const std::string& keyword, float fallback, int line) {
    auto w = word();
    if (!w) {
      warn(keyword, "missing numeric argument", line);
      return fallback;
    }
    auto v = parseNumber(*w);
    if (!v) {
      warn(keyword, "'" + *w + "' is not a number", line);
      return fallback;
    }
    return *v;
  }
  /// Reads N numbers written as "( a b c )", tolerating parentheses glued to numbers.
  template <size_t N>
  std::array<float, N> vector(const std::string& keyword, int line) {
    std::array<float, N> v{};
    size_t n = 0;
    bool open = false;
    while (n < N) {
      const auto m = tok_.mark();
      auto w = word();
      if (!w) break;
      std::string_view s = *w;
      if (!s.empty() && s.front() == '(') {
        open = true;
        s.remove_prefix(1);
      }
      bool closes = false;
      if (!s.empty() && s.back() == ')') {
        closes = true;
        s.remove_suffix(1);
      }
      if (!s.empty()) {
        auto value = parseNumber(s);
        if (!value) {
          tok_.reset(m);
          break;
        }
        v[n++] = *value;
      }
      if (closes) break;
    }
    if (n < N) warn(keyword, "expected " + std::to_string(N) + " numbers", line);
    if (open) {  // consume a separate closing parenthesis
      const auto m = tok_.mark();
      auto w = word();
      if (!w || *w != ")") tok_.reset(m);
    }
    return v;
  }
  WaveForm wave(const std::string& keyword, int line) {
    WaveForm w;
    auto name = word();
    if (!name) {
      warn(keyword, "missing wave function", line);
      return w;
    }
    if (auto f = waveFuncFromName(*name)) w.func = *f;
    else warn(keyword, "unknown wave function '" + *name + "'", line);
    w.base = number(keyword, 0, line);
    w.amplitude = number(keyword, 0, line);
    w.phase = number(keyword, 0, line);
    w.frequency = number(keyword, 0, line);
    return w;
  }

  // ---- shader body ----
  void parseBody(ShaderDef& def) {
    for (;;) {
      auto t = tok_.next();
      if (!t)
        throw FormatError(file_, "shader '" + def.name + "' (line " + std::to_string(def.line) + ")",
                          "missing closing brace");
      if (!t->quoted && t->text == "}") return;
      if (!t->quoted && t->text == "{") {
        ShaderStage stage;
        parseStage(stage);
        if (def.stages.size() < ShaderLimits::maxStages) def.stages.push_back(std::move(stage));
        else warn("{", "too many stages, stage ignored", t->line);
        continue;
      }
      parseGeneral(def, toLowerAscii(t->text), t->line);
    }
  }

  void parseGeneral(ShaderDef& def, const std::string& k, int line) {
    if (k == "surfaceparm") {
      auto name = word();
      if (!name) return warn(k, "missing surfaceparm name", line);
      if (auto bit = surfaceParmFromName(*name)) def.surfaceParms |= static_cast<uint64_t>(*bit);
      else unknown("surfaceparm " + toLowerAscii(*name), "surfaceparm", line);
    } else if (k == "cull") {
      auto mode = word();
      if (!mode) return warn(k, "missing cull mode", line);
      const std::string m = toLowerAscii(*mode);
      if (m == "none" || m == "twosided" || m == "disable") def.cull = CullMode::TwoSided;
      else if (m == "back" || m == "backside" || m == "backsided") def.cull = CullMode::BackSided;
      else if (m == "front" || m == "frontside" || m == "frontsided") def.cull = CullMode::FrontSided;
      else warn(k, "unknown cull mode '" + *mode + "'", line);
    } else if (k == "deformvertexes") {
      parseDeform(def, line);
    } else if (k == "sort") {
      parseSort(def, line);
    } else if (k == "q3map_surfacelight") {
      def.surfaceLight = number(k, 0, line);
    } else if (k == "q3map_lightimage") {
      if (auto w = word()) def.lightImage = *w;
      else warn(k, "missing image", line);
    } else if (k == "q3map_lightrgb") {
      def.lightColor = vector<3>(k, line);
    } else if (k == "q3map_sun" || k == "q3map_sunext") {
      SunParms sun;
      sun.color = vector<3>(k, line);
      sun.intensity = number(k, 0, line);
      sun.degrees = number(k, 0, line);
      sun.elevation = number(k, 0, line);
      if (k == "q3map_sunext") {
        sun.deviation = number(k, 0, line);
        skipArgs();  // sample count
      }
      def.sun = sun;
    } else if (k == "qer_editorimage") {
      if (auto w = word()) def.editorImage = *w;
    } else if (k == "skyparms") {
      SkyParms sky;
      auto far = word(), cloud = word(), near = word();
      if (!far || !cloud || !near) warn(k, "expected <farbox> <cloudheight> <nearbox>", line);
      if (far && *far != "-") sky.farBox = *far;
      if (cloud && *cloud != "-") {
        if (auto h = parseNumber(*cloud)) sky.cloudHeight = *h;
      }
      if (near && *near != "-") sky.nearBox = *near;
      def.sky = sky;
    } else if (k == "fogparms") {
      FogParms fog;
      fog.color = vector<3>(k, line);
      fog.depthForOpaque = number(k, 0, line);
      skipArgs();
      def.fog = fog;
    } else if (k == "portal") {
      def.portal = true;
    } else if (k == "polygonoffset") {
      def.polygonOffset = true;
    } else if (k == "nopicmip") {
      def.noPicmip = true;
    } else if (k == "nomipmaps") {
      def.noMipmaps = true;
    } else if (k == "entitymergable") {
      def.entityMergable = true;
    } else if (k == "light" || k == "clamptime" || k == "tesssize" || k.starts_with("q3map_") ||
               k.starts_with("qer_")) {
      CompilerDirective d{k, {}};
      while (auto w = word()) d.args.push_back(*w);
      def.compilerDirectives.push_back(std::move(d));
    } else {
      unknown(k, "shader keyword", line);
      skipArgs();
    }
  }

  void parseDeform(ShaderDef& def, int line) {
    const std::string k = "deformvertexes";
    auto kindWord = word();
    if (!kindWord) return warn(k, "missing deform type", line);
    const std::string kind = toLowerAscii(*kindWord);
    Deform d;
    if (kind == "wave") {
      d.kind = DeformKind::Wave;
      d.spread = number(k, 0, line);
      d.wave = wave(k, line);
    } else if (kind == "normal") {
      d.kind = DeformKind::Normal;
      d.params[0] = number(k, 0, line);
      d.params[1] = number(k, 0, line);
    } else if (kind == "bulge") {
      d.kind = DeformKind::Bulge;
      for (int i = 0; i < 3; ++i) d.params[i] = number(k, 0, line);
    } else if (kind == "move") {
      d.kind = DeformKind::Move;
      for (int i = 0; i < 3; ++i) d.params[i] = number(k, 0, line);
      d.wave = wave(k, line);
    } else if (kind == "autosprite") {
      d.kind = DeformKind::AutoSprite;
    } else if (kind == "autosprite2") {
      d.kind = DeformKind::AutoSprite2;
    } else if (kind == "projectionshadow") {
      d.kind = DeformKind::ProjectionShadow;
    } else if (kind.size() == 5 && kind.starts_with("text") && kind[4] >= '0' && kind[4] <= '7') {
      d.kind = DeformKind::Text;
      d.textIndex = kind[4] - '0';
    } else {
      unknown("deformvertexes " + kind, "deform", line);
      return skipArgs();
    }
    skipArgs();
    if (def.deforms.size() < ShaderLimits::maxDeforms) def.deforms.push_back(d);
    else warn(k, "too many deforms", line);
  }

  void parseSort(ShaderDef& def, int line) {
    auto w = word();
    if (!w) return warn("sort", "missing sort value", line);
    static const std::pair<const char*, float> kSorts[] = {
        {"portal", sort_key::Portal}, {"sky", sort_key::Environment},
        {"opaque", sort_key::Opaque}, {"decal", sort_key::Decal},
        {"seethrough", sort_key::SeeThrough}, {"banner", sort_key::Banner},
        {"additive", sort_key::Blend1}, {"nearest", sort_key::Nearest},
        {"underwater", sort_key::Underwater},
    };
    for (const auto& [name, value] : kSorts)
      if (equalsIgnoreCase(*w, name)) {
        def.sort = value;
        return;
      }
    if (auto v = parseNumber(*w)) def.sort = *v;
    else warn("sort", "unknown sort value '" + *w + "'", line);
  }

  // ---- stages ----
  void parseStage(ShaderStage& stage) {
    for (;;) {
      auto t = tok_.next();
      if (!t)
        throw FormatError(file_, "shader '" + current_->name + "' stage", "missing closing brace");
      if (!t->quoted && t->text == "}") {
        markExternalLightmap(stage);
        return;
      }
      if (!t->quoted && t->text == "{") {
        warn("{", "nested block inside a stage ignored", t->line);
        if (!tok_.skipBracedSection())
          throw FormatError(file_, "shader '" + current_->name + "' stage", "missing closing brace");
        continue;
      }
      parseStageKeyword(stage, toLowerAscii(t->text), t->line);
    }
  }

  void parseStageKeyword(ShaderStage& s, const std::string& k, int line) {
    if (k == "map" || k == "clampmap") {
      auto path = word();
      if (!path) return warn(k, "missing texture", line);
      s.textures = {*path};
      s.clamp = (k == "clampmap");
      if (equalsIgnoreCase(*path, "$lightmap")) s.source = TextureSource::Lightmap;
      else if (equalsIgnoreCase(*path, "$whiteimage")) s.source = TextureSource::WhiteImage;
      else s.source = TextureSource::Image;
    } else if (k == "animmap") {
      s.source = TextureSource::Image;
      s.animFrequency = number(k, 0, line);
      s.textures.clear();
      while (auto frame = word()) {
        if (s.textures.size() < ShaderLimits::maxAnimFrames) s.textures.push_back(*frame);
        else warn(k, "more than 8 frames, '" + *frame + "' ignored", line);
      }
      if (s.textures.empty()) warn(k, "no frames", line);
    } else if (k == "videomap") {
      auto path = word();
      if (!path) return warn(k, "missing video", line);
      s.source = TextureSource::Video;
      s.textures = {*path};
    } else if (k == "alphafunc") {
      auto f = word();
      if (!f) return warn(k, "missing function", line);
      if (equalsIgnoreCase(*f, "gt0")) s.alphaTest = AlphaTest::Gt0;
      else if (equalsIgnoreCase(*f, "lt128")) s.alphaTest = AlphaTest::Lt128;
      else if (equalsIgnoreCase(*f, "ge128")) s.alphaTest = AlphaTest::Ge128;
      else warn(k, "unknown alpha function '" + *f + "'", line);
    } else if (k == "depthfunc") {
      auto f = word();
      if (!f) return warn(k, "missing function", line);
      if (equalsIgnoreCase(*f, "equal")) s.depthEqual = true;
      else if (equalsIgnoreCase(*f, "lequal")) s.depthEqual = false;
      else warn(k, "unknown depth function '" + *f + "'", line);
    } else if (k == "depthwrite") {
      s.depthWrite = true;
    } else if (k == "detail") {
      s.detail = true;
    } else if (k == "blendfunc") {
      parseBlend(s, line);
    } else if (k == "rgbgen") {
      parseRgbGen(s, line);
    } else if (k == "alphagen") {
      parseAlphaGen(s, line);
    } else if (k == "tcgen" || k == "texgen") {
      parseTcGen(s, line);
    } else if (k == "tcmod") {
      parseTcMod(s, line);
    } else {
      unknown(k, "stage keyword", line);
      skipArgs();
    }
  }

  void parseBlend(ShaderStage& s, int line) {
    const std::string k = "blendfunc";
    auto first = word();
    if (!first) return warn(k, "missing blend mode", line);
    s.hasBlend = true;
    if (equalsIgnoreCase(*first, "add")) {
      s.srcBlend = BlendFactor::One, s.dstBlend = BlendFactor::One;
    } else if (equalsIgnoreCase(*first, "filter")) {
      s.srcBlend = BlendFactor::DstColor, s.dstBlend = BlendFactor::Zero;
    } else if (equalsIgnoreCase(*first, "blend")) {
      s.srcBlend = BlendFactor::SrcAlpha, s.dstBlend = BlendFactor::OneMinusSrcAlpha;
    } else {
      auto second = word();
      auto src = blendFactorFromName(*first);
      auto dst = second ? blendFactorFromName(*second) : std::nullopt;
      // The engine substitutes GL_ONE for an unknown factor; so do we, with a warning.
      if (!src) warn(k, "unknown source factor '" + *first + "'", line);
      if (!dst) warn(k, "unknown or missing destination factor", line);
      s.srcBlend = src.value_or(BlendFactor::One);
      s.dstBlend = dst.value_or(BlendFactor::One);
    }
  }

  void parseRgbGen(ShaderStage& s, int line) {
    const std::string k = "rgbgen";
    auto w = word();
    if (!w) return warn(k, "missing mode", line);
    const std::string m = toLowerAscii(*w);
    static const std::pair<const char*, RgbGen> kSimple[] = {
        {"identity", RgbGen::Identity}, {"identitylighting", RgbGen::IdentityLighting},
        {"vertex", RgbGen::Vertex}, {"exactvertex", RgbGen::ExactVertex},
        {"oneminusvertex", RgbGen::OneMinusVertex}, {"lightingdiffuse", RgbGen::LightingDiffuse},
        {"entity", RgbGen::Entity}, {"oneminusentity", RgbGen::OneMinusEntity},
    };
    for (const auto& [name, mode] : kSimple)
      if (m == name) {
        s.rgbGen = mode;
        return;
      }
    if (m == "wave") {
      s.rgbGen = RgbGen::Wave;
      s.rgbWave = wave(k, line);
    } else if (m == "const") {
      s.rgbGen = RgbGen::Const;
      s.constColor = vector<3>(k, line);
    } else {
      unknown("rgbgen " + m, "rgbGen mode", line);
    }
  }

  void parseAlphaGen(ShaderStage& s, int line) {
    const std::string k = "alphagen";
    auto w = word();
    if (!w) return warn(k, "missing mode", line);
    const std::string m = toLowerAscii(*w);
    static const std::pair<const char*, AlphaGen> kSimple[] = {
        {"identity", AlphaGen::Identity}, {"vertex", AlphaGen::Vertex},
        {"oneminusvertex", AlphaGen::OneMinusVertex}, {"entity", AlphaGen::Entity},
        {"oneminusentity", AlphaGen::OneMinusEntity}, {"lightingspecular", AlphaGen::LightingSpecular},
    };
    for (const auto& [name, mode] : kSimple)
      if (m == name) {
        s.alphaGen = mode;
        return;
      }
    if (m == "wave") {
      s.alphaGen = AlphaGen::Wave;
      s.alphaWave = wave(k, line);
    } else if (m == "const") {
      s.alphaGen = AlphaGen::Const;
      s.constAlpha = number(k, 1, line);
    } else if (m == "portal") {
      s.alphaGen = AlphaGen::Portal;
      s.portalRange = number(k, 256, line);
    } else {
      unknown("alphagen " + m, "alphaGen mode", line);
    }
  }

  void parseTcGen(ShaderStage& s, int line) {
    const std::string k = "tcgen";
    auto w = word();
    if (!w) return warn(k, "missing mode", line);
    const std::string m = toLowerAscii(*w);
    if (m == "base" || m == "texture") s.tcGen = TcGen::Base;
    else if (m == "lightmap") s.tcGen = TcGen::Lightmap;
    else if (m == "environment") s.tcGen = TcGen::Environment;
    else if (m == "vector") {
      s.tcGen = TcGen::Vector;
      s.tcGenVectors[0] = vector<3>(k, line);
      s.tcGenVectors[1] = vector<3>(k, line);
    } else {
      unknown("tcgen " + m, "tcGen mode", line);
    }
  }

  void parseTcMod(ShaderStage& s, int line) {
    const std::string k = "tcmod";
    auto w = word();
    if (!w) return warn(k, "missing type", line);
    const std::string m = toLowerAscii(*w);
    TcMod mod;
    if (m == "scroll" || m == "scale") {
      mod.kind = m == "scroll" ? TcModKind::Scroll : TcModKind::Scale;
      mod.scroll[0] = number(k, 0, line);
      mod.scroll[1] = number(k, 0, line);
    } else if (m == "rotate") {
      mod.kind = TcModKind::Rotate;
      mod.degreesPerSecond = number(k, 0, line);
    } else if (m == "stretch") {
      mod.kind = TcModKind::Stretch;
      mod.wave = wave(k, line);
    } else if (m == "turb") {
      // "turb <base> <amp> <phase> <freq>"; some scripts add a "sin" the engine does not expect.
      mod.kind = TcModKind::Turb;
      const auto mark = tok_.mark();
      auto maybeFunc = word();
      if (!maybeFunc || !waveFuncFromName(*maybeFunc)) tok_.reset(mark);
      mod.wave.base = number(k, 0, line);
      mod.wave.amplitude = number(k, 0, line);
      mod.wave.phase = number(k, 0, line);
      mod.wave.frequency = number(k, 0, line);
    } else if (m == "transform") {
      mod.kind = TcModKind::Transform;
      for (float& v : mod.matrix) v = number(k, 0, line);
      for (float& v : mod.translate) v = number(k, 0, line);
    } else if (m == "entitytranslate") {
      mod.kind = TcModKind::EntityTranslate;
    } else {
      unknown("tcmod " + m, "tcMod type", line);
      return skipArgs();
    }
    skipArgs();
    if (s.tcMods.size() < ShaderLimits::maxTcMods) s.tcMods.push_back(mod);
    else warn(k, "too many tcMods", line);
  }

  Tokenizer tok_;
  std::string file_;
  ShaderDef* current_ = nullptr;
  std::vector<ShaderWarning> warnings_;
  std::map<std::string, size_t> unknownIndex_;
};

}  // namespace

float WaveForm::evaluate(double seconds) const {
  return base + amplitude * waveTableValue(func, phase + seconds * frequency);
}

std::optional<SurfaceParm> surfaceParmFromName(std::string_view name) {
  for (const auto& p : kSurfaceParms)
    if (equalsIgnoreCase(name, p.name)) return p.bit;
  return std::nullopt;
}

ShaderScript parseShaderScript(std::string_view text, const std::string& file) {
  return ScriptParser(text, file).run();
}

}  // namespace q3
