// Arena list parsing (on the formats library's Quake tokenizer) and the spawn family of a game type.
#include "tests/all_maps_render/arena_info.h"

#include <algorithm>
#include <array>

#include "port/q3formats/common/tokenizer.h"

namespace pa::allmaps {
namespace {

/// Where the game reads a game type word of an arena's "type" (OpenArena's ui_gameinfo.c names)
/// and which spawn points ClientSpawn uses for it: the base-oriented team games
/// (gametype >= GT_CTF, not FFA-like, not domination) use the CTF team spawns.
struct GameTypeWord {
  std::string_view word;
  SpawnFamily family;
};
constexpr std::array<GameTypeWord, 18> kGameTypes = {{
    {"single", SpawnFamily::Deathmatch},   {"ffa", SpawnFamily::Deathmatch},
    {"tourney", SpawnFamily::Deathmatch},  {"team", SpawnFamily::Deathmatch},
    {"tdm", SpawnFamily::Deathmatch},      {"lms", SpawnFamily::Deathmatch},
    {"dom", SpawnFamily::Deathmatch},      {"pos", SpawnFamily::Deathmatch},
    {"dd", SpawnFamily::Deathmatch},       {"ctf", SpawnFamily::Team},
    {"oneflag", SpawnFamily::Team},        {"1fctf", SpawnFamily::Team},
    {"overload", SpawnFamily::Team},       {"obelisk", SpawnFamily::Team},
    {"harvester", SpawnFamily::Team},      {"elimination", SpawnFamily::Team},
    {"ctfelimination", SpawnFamily::Team}, {"ctfelim", SpawnFamily::Team},
}};

/// True when the game's info strings can hold `text` (Info_SetValueForKey refuses \ ; and ").
bool storableInInfo(std::string_view text) { return text.find_first_of("\\;\"") == std::string_view::npos; }

}  // namespace

std::optional<std::string_view> ArenaInfo::get(std::string_view key) const {
  for (const auto& [k, v] : keys)
    if (q3::equalsIgnoreCase(k, key)) return std::string_view(v);
  return std::nullopt;
}

std::vector<ArenaInfo> parseArenaInfos(std::string_view text, const std::string& fileName,
                                       std::vector<std::string>& warnings, const ArenaParseLimits& limits) {
  std::vector<ArenaInfo> infos;
  q3::Tokenizer::Options options;
  options.maxTokenLength = limits.maxTokenLength;
  q3::Tokenizer tokens(text, fileName, options);
  auto warn = [&](int line, const std::string& what) {
    warnings.push_back(fileName + ":" + std::to_string(line) + ": " + what);
  };
  while (const std::optional<q3::Token> open = tokens.next()) {
    if (open->text != "{") {
      warn(open->line, "expected '{', found \"" + open->text.substr(0, 32) + "\"; the rest of the file is ignored");
      break;
    }
    if (infos.size() >= limits.maxBlocks) {
      warn(open->line, "more than " + std::to_string(limits.maxBlocks) + " blocks; the rest of the file is ignored");
      break;
    }
    ArenaInfo& info = infos.emplace_back();
    for (;;) {
      const std::optional<q3::Token> key = tokens.next();
      if (!key || key->text.empty()) {   // the game stops at an empty token as at the end
        warn(key ? key->line : tokens.line(), "block opened at line " + std::to_string(open->line) + " is not closed");
        break;
      }
      if (key->text == "}") break;
      const std::optional<q3::Token> value = tokens.nextOnLine();
      const std::string valueText = value && !value->text.empty() ? value->text : "<NULL>";
      if (!storableInInfo(key->text) || !storableInInfo(valueText)) {
        warn(key->line, "key \"" + key->text.substr(0, 32) + "\" or its value holds \\, ; or \"; ignored");
        continue;
      }
      // A repeated key replaces the earlier value, as in the game's info string.
      const auto same = std::find_if(info.keys.begin(), info.keys.end(),
                                     [&](const auto& kv) { return q3::equalsIgnoreCase(kv.first, key->text); });
      if (same != info.keys.end()) {
        same->second = valueText;
      } else if (info.keys.size() < limits.maxKeysPerBlock) {
        info.keys.emplace_back(key->text, valueText);
      } else {
        warn(key->line, "more than " + std::to_string(limits.maxKeysPerBlock) + " keys in a block; \"" +
                            key->text.substr(0, 32) + "\" ignored");
      }
    }
  }
  return infos;
}

std::optional<SpawnFamily> spawnFamilyOfGameType(std::string_view gameType) {
  for (const GameTypeWord& g : kGameTypes)
    if (q3::equalsIgnoreCase(g.word, gameType)) return g.family;
  return std::nullopt;
}

std::vector<std::string> splitGameTypes(std::string_view typeValue) {
  std::vector<std::string> words;
  size_t start = 0;
  while (start < typeValue.size()) {
    const size_t end = std::min(typeValue.find_first_of(" \t,", start), typeValue.size());
    if (end > start) words.push_back(q3::toLowerAscii(typeValue.substr(start, end - start)));
    start = end + 1;
  }
  return words;
}

void ArenaIndex::addFile(std::string_view text, const std::string& fileName, std::vector<std::string>& warnings) {
  for (const ArenaInfo& info : parseArenaInfos(text, fileName, warnings)) {
    const std::optional<std::string_view> map = info.get("map");
    if (!map || map->empty() || find(*map)) continue;   // the game takes a map's first entry
    ArenaEntry entry;
    entry.file = fileName;
    entry.type = std::string(info.get("type").value_or(""));
    for (const std::string& word : splitGameTypes(entry.type))
      if (const std::optional<SpawnFamily> family = spawnFamilyOfGameType(word)) {
        entry.gameType = word;
        entry.family = family;
        break;
      }
    entries_.emplace_back(q3::toLowerAscii(*map), std::move(entry));
  }
}

const ArenaEntry* ArenaIndex::find(std::string_view map) const {
  for (const auto& [name, entry] : entries_)
    if (q3::equalsIgnoreCase(name, map)) return &entry;
  return nullptr;
}

}  // namespace pa::allmaps
