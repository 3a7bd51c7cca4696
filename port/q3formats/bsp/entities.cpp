// Entity lump parser and typed views.
#include "port/q3formats/bsp/entities.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>

#include "port/q3formats/common/format_error.h"

namespace q3 {
namespace {

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

/// Splits entity text into '{', '}' and string tokens (quoted or bare), skipping comments.
class EntityTokenizer {
 public:
  EntityTokenizer(std::string_view text, const std::string& file, size_t maxToken)
      : text_(text), file_(file), maxToken_(maxToken) {}

  /// Next token, or nullopt at end of text. `quoted` tells whether it was a quoted string.
  std::optional<std::string_view> next(bool& quoted) {
    skipSpaceAndComments();
    quoted = false;
    if (pos_ >= text_.size()) return std::nullopt;
    const size_t start = pos_;
    if (text_[pos_] == '"') {
      const size_t close = text_.find('"', pos_ + 1);
      if (close == std::string_view::npos) fail("unterminated quoted string", start);
      pos_ = close + 1;
      quoted = true;
      return checked(text_.substr(start + 1, close - start - 1), start);
    }
    if (text_[pos_] == '{' || text_[pos_] == '}') return text_.substr(pos_++, 1);
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_])) &&
           text_[pos_] != '"' && text_[pos_] != '{' && text_[pos_] != '}')
      ++pos_;
    return checked(text_.substr(start, pos_ - start), start);
  }

  [[noreturn]] void fail(const std::string& detail, size_t at) const {
    throw FormatError(file_, "entities", detail + " at line " + std::to_string(lineOf(at)));
  }

 private:
  std::string_view checked(std::string_view token, size_t at) const {
    if (token.size() > maxToken_)
      fail("token of " + std::to_string(token.size()) + " characters exceeds limit " +
               std::to_string(maxToken_),
           at);
    return token;
  }
  void skipSpaceAndComments() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (std::isspace(static_cast<unsigned char>(c)) || c == '\0') {
        ++pos_;
      } else if (text_.substr(pos_, 2) == "//") {
        const size_t eol = text_.find('\n', pos_);
        pos_ = eol == std::string_view::npos ? text_.size() : eol + 1;
      } else if (text_.substr(pos_, 2) == "/*") {
        const size_t end = text_.find("*/", pos_ + 2);
        if (end == std::string_view::npos) fail("unterminated block comment", pos_);
        pos_ = end + 2;
      } else {
        return;
      }
    }
  }
  size_t lineOf(size_t at) const {
    return 1 + static_cast<size_t>(std::count(text_.begin(), text_.begin() + std::min(at, text_.size()), '\n'));
  }

  std::string_view text_;
  const std::string& file_;
  size_t maxToken_;
  size_t pos_ = 0;
};

std::optional<float> parseFloat(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  float value = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || end == s.data() || !std::isfinite(value)) return std::nullopt;
  return value;
}

glm::vec3 normalisedColor(const Entity& e) {
  const auto c = e.getVec3("_color");
  if (!c) return glm::vec3(1);
  const glm::vec3 clamped = glm::max(*c, glm::vec3(0));
  const float m = std::max({clamped.x, clamped.y, clamped.z});
  return m > 0 ? clamped / m : glm::vec3(1);
}

glm::vec3 normalize(const glm::vec3& v) {
  const float len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  return len > 0 ? v / len : glm::vec3(0, 0, -1);
}

}  // namespace

const std::string* Entity::find(std::string_view key) const {
  for (const auto& [k, v] : keys)
    if (equalsIgnoreCase(k, key)) return &v;
  return nullptr;
}

std::string_view Entity::get(std::string_view key, std::string_view fallback) const {
  const auto* v = find(key);
  return v ? std::string_view(*v) : fallback;
}

float Entity::getFloat(std::string_view key, float fallback) const {
  const auto* v = find(key);
  if (!v) return fallback;
  return parseFloat(*v).value_or(fallback);
}

std::optional<glm::vec3> Entity::getVec3(std::string_view key) const {
  const auto* v = find(key);
  if (!v) return std::nullopt;
  glm::vec3 out{};
  std::string_view rest = *v;
  for (int k = 0; k < 3; ++k) {
    while (!rest.empty() && std::isspace(static_cast<unsigned char>(rest.front()))) rest.remove_prefix(1);
    const size_t end = std::min(rest.find_first_of(" \t\r\n"), rest.size());
    const auto f = parseFloat(rest.substr(0, end));
    if (!f) return std::nullopt;
    out[k] = *f;
    rest.remove_prefix(end);
  }
  return out;
}

std::vector<Entity> parseEntities(std::string_view text, const std::string& fileName,
                                  const EntityParseLimits& limits) {
  std::vector<Entity> entities;
  EntityTokenizer tokens(text, fileName, limits.maxTokenLength);
  bool quoted = false;
  while (auto token = tokens.next(quoted)) {
    if (quoted || *token != "{")
      throw FormatError(fileName, "entities",
                        "expected '{' before entity " + std::to_string(entities.size()) +
                            ", found \"" + std::string(token->substr(0, 32)) + "\"");
    if (entities.size() >= limits.maxEntities)
      throw FormatError(fileName, "entities", "more than " + std::to_string(limits.maxEntities) + " entities");
    Entity& entity = entities.emplace_back();
    for (;;) {
      auto key = tokens.next(quoted);
      if (!key)
        throw FormatError(fileName, "entities",
                          "entity " + std::to_string(entities.size() - 1) + " is not closed by '}'");
      if (!quoted && *key == "}") break;
      if (!quoted && *key == "{")
        throw FormatError(fileName, "entities", "'{' inside entity " + std::to_string(entities.size() - 1));
      const std::string keyText(*key);
      auto value = tokens.next(quoted);
      if (!value || (!quoted && (*value == "}" || *value == "{")))
        throw FormatError(fileName, "entities",
                          "key \"" + keyText.substr(0, 32) + "\" of entity " +
                              std::to_string(entities.size() - 1) + " has no value");
      if (entity.keys.size() >= limits.maxKeysPerEntity)
        throw FormatError(fileName, "entities", "entity " + std::to_string(entities.size() - 1) +
                                                    " has more than " +
                                                    std::to_string(limits.maxKeysPerEntity) + " keys");
      entity.keys.emplace_back(keyText, std::string(*value));
    }
  }
  return entities;
}

std::optional<Entity> findWorldspawn(const std::vector<Entity>& entities) {
  for (const auto& e : entities)
    if (equalsIgnoreCase(e.className(), "worldspawn")) return e;
  return std::nullopt;
}

glm::vec3 worldspawnGridSize(const Entity& worldspawn, std::vector<std::string>& warnings) {
  const glm::vec3 fallback{64, 64, 128};
  if (!worldspawn.find("gridsize")) return fallback;
  const auto g = worldspawn.getVec3("gridsize");
  if (!g || g->x < 1 || g->y < 1 || g->z < 1) {
    warnings.push_back("worldspawn gridsize \"" + std::string(worldspawn.get("gridsize")) +
                       "\" is not three numbers >= 1; using 64 64 128");
    return fallback;
  }
  return *g;
}

WorldspawnInfo readWorldspawn(const std::vector<Entity>& entities) {
  WorldspawnInfo info;
  const auto world = findWorldspawn(entities);
  if (!world) return info;
  info.message = std::string(world->get("message"));
  info.gridSize = worldspawnGridSize(*world, info.warnings);
  info.color = normalisedColor(*world);
  const float ambient = world->getFloat("_ambient", world->getFloat("ambient", 0));
  info.ambient = info.color * std::max(ambient, 0.0f);
  const float minlight = world->getFloat("_minlight", world->getFloat("minlight", 0));
  info.minlight = info.color * std::max(minlight, 0.0f);
  return info;
}

std::vector<LightEntity> readLights(const std::vector<Entity>& entities) {
  std::vector<LightEntity> lights;
  for (const auto& e : entities) {
    if (!equalsIgnoreCase(e.className(), "light")) continue;
    LightEntity light;
    light.origin = e.getVec3("origin").value_or(glm::vec3(0));
    float intensity = e.getFloat("_light", 0);
    if (intensity == 0) intensity = e.getFloat("light", 0);
    if (intensity == 0) intensity = 300;
    light.intensity = intensity * e.getFloat("scale", 1);
    light.color = normalisedColor(e);
    const float flags = e.getFloat("spawnflags", 0);
    const int spawnflags = (flags >= 0 && flags < 65536) ? static_cast<int>(flags) : 0;
    light.linearFalloff = spawnflags & 1;
    light.noIncidence = spawnflags & 2;
    const std::string_view target = e.get("target");
    if (!target.empty()) {
      for (const auto& t : entities) {
        if (t.get("targetname") != target) continue;
        const auto dest = t.getVec3("origin");
        if (!dest) continue;
        const glm::vec3 delta = *dest - light.origin;
        float dist = std::sqrt(delta.x * delta.x + delta.y * delta.y + delta.z * delta.z);
        light.isSpot = true;
        light.spotDirection = normalize(delta);
        if (dist <= 0) dist = 64;
        float radius = e.getFloat("radius", 64);
        if (radius <= 0) radius = 64;
        const float cone = e.getFloat("_cone", 0);
        light.spotConeHalfAngleDeg = (cone > 0 && cone < 180)
                                         ? cone
                                         : std::atan(radius / dist) * 180.0f / std::numbers::pi_v<float>;
        break;
      }
    }
    lights.push_back(light);
  }
  return lights;
}

void anglesToAxes(const glm::vec3& anglesDeg, glm::vec3& forward, glm::vec3& left, glm::vec3& up) {
  const float toRad = std::numbers::pi_v<float> / 180.0f;
  const float sp = std::sin(anglesDeg.x * toRad), cp = std::cos(anglesDeg.x * toRad);
  const float sy = std::sin(anglesDeg.y * toRad), cy = std::cos(anglesDeg.y * toRad);
  const float sr = std::sin(anglesDeg.z * toRad), cr = std::cos(anglesDeg.z * toRad);
  // Yaw about +Z, then pitch about the new left axis (positive looks down), then roll about forward.
  forward = {cp * cy, cp * sy, -sp};
  left = {sr * sp * cy - cr * sy, sr * sp * sy + cr * cy, sr * cp};
  up = {cr * sp * cy + sr * sy, cr * sp * sy - sr * cy, cr * cp};
}

namespace {

/// Deathmatch/start/intermission spawns (0), CTF team spawns (1), or not a spawn point (-1).
int spawnRank(std::string_view cls) {
  for (const char* name : {"info_player_deathmatch", "info_player_start", "info_player_intermission"})
    if (equalsIgnoreCase(cls, name)) return 0;
  for (const char* name : {"team_CTF_redspawn", "team_CTF_bluespawn", "team_CTF_redplayer", "team_CTF_blueplayer"})
    if (equalsIgnoreCase(cls, name)) return 1;
  return -1;
}

}  // namespace

std::vector<SpawnCamera> readSpawnCameras(const std::vector<Entity>& entities) {
  std::vector<SpawnCamera> cameras;
  for (int rank : {0, 1})
    for (const auto& e : entities) {
      const std::string_view cls = e.className();
      if (spawnRank(cls) != rank) continue;
      const bool intermission = equalsIgnoreCase(cls, "info_player_intermission");
      SpawnCamera cam;
      cam.className = std::string(cls);
      cam.origin = e.getVec3("origin").value_or(glm::vec3(0));
      cam.eye = intermission ? cam.origin : cam.origin + glm::vec3(0, 0, kSpawnEyeHeight);
      if (const auto angles = e.getVec3("angles")) cam.angles = *angles;
      else cam.angles = {0, e.getFloat("angle", 0), 0};
      anglesToAxes(cam.angles, cam.forward, cam.left, cam.up);
      cameras.push_back(cam);
    }
  return cameras;
}

}  // namespace q3
