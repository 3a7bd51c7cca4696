#pragma once
// The game's arena lists (scripts/arenas.txt, scripts/*.arena): which game types each map is
// listed for, and so which kind of player spawn a player of its first game type starts at.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pa::allmaps {

/// One `{ key "value" ... }` block of an arena file (keys in file order, first match wins).
struct ArenaInfo {
  std::vector<std::pair<std::string, std::string>> keys;
  /// Value of `key` (case-insensitive), or nullopt.
  std::optional<std::string_view> get(std::string_view key) const;
};

/// Limits on an arena file (hostile input: a pk3 from a game server).
struct ArenaParseLimits {
  size_t maxBlocks = 4096;        ///< Blocks read per file; later ones are dropped with a warning.
  size_t maxKeysPerBlock = 64;    ///< Keys read per block; later ones are dropped with a warning.
  size_t maxTokenLength = 1024;   ///< Longer keys or values are cut (the engine's MAX_TOKEN_CHARS).
};

/// Parses arena text the way the game reads its info files: blocks `{ ... }` of a key token and
/// its value (the next token on the same line; none gives "<NULL>"), `//` and `/* */` comments,
/// quotes optional. Never throws: a block without `{`, a block cut off by the end of the text or
/// an exceeded limit ends the reading and adds a warning naming `fileName` and the line, and the
/// blocks read so far are kept.
std::vector<ArenaInfo> parseArenaInfos(std::string_view text, const std::string& fileName,
                                       std::vector<std::string>& warnings, const ArenaParseLimits& limits = {});

/// Which spawn points a game type starts its players at (OpenArena's g_client.c, ClientSpawn).
enum class SpawnFamily {
  Deathmatch,   ///< info_player_deathmatch / info_player_start: ffa, tourney, team, lms, dom, single, dd*.
  Team,         ///< team_CTF_redplayer / blueplayer, then team_CTF_redspawn / bluespawn: ctf and the other base games.
};

/// The spawn family of one game type word of an arena's "type" ("ctf", "oneflag", "ffa", ...,
/// case-insensitive); nullopt for a word the game does not know. `dd` starts players at
/// info_player_dd_red/blue, which are no cameras, and falls back to the deathmatch spawns.
std::optional<SpawnFamily> spawnFamilyOfGameType(std::string_view gameType);

/// The game type words of an arena's "type" value, split at spaces, tabs and commas, lower case.
std::vector<std::string> splitGameTypes(std::string_view typeValue);

/// A map's arena entry as far as the spawn choice is concerned.
struct ArenaEntry {
  std::string file;                  ///< Arena file the entry was read from.
  std::string type;                  ///< Its "type" value as written.
  std::string gameType;              ///< The first game type word the game knows ("" if none).
  std::optional<SpawnFamily> family; ///< Spawn family of `gameType` (nullopt if none).
};

/// The game's arena entries by map name: the first entry for a map wins, files read in the order
/// added (the game reads scripts/arenas.txt, then scripts/*.arena).
class ArenaIndex {
 public:
  /// Adds the blocks of one arena file (parseArenaInfos; its warnings are appended to `warnings`).
  void addFile(std::string_view text, const std::string& fileName, std::vector<std::string>& warnings);
  /// The entry of `map` ("oa_dm1", case-insensitive), or nullptr when no arena file lists it.
  const ArenaEntry* find(std::string_view map) const;
  /// Number of maps listed.
  size_t size() const { return entries_.size(); }

 private:
  std::vector<std::pair<std::string, ArenaEntry>> entries_;   ///< Lower-case map name, entry.
};

}  // namespace pa::allmaps
