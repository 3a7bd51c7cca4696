// Known-answer tests of the arena list reader: the game's info-file syntax as OpenArena ships
// it (comments, unquoted values, commas in "type", a stray brace) and malformed input.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "tests/all_maps_render/arena_info.h"

namespace pa::allmaps {
namespace {

TEST(ArenaInfo, ReadsBlocksWithCommentsAndUnquotedValues) {
  std::vector<std::string> warnings;
  const auto infos = parseArenaInfos(R"(//Tier 1
{
map		"oa_rpg3dm2"
longname	"Trial By Error"   /* a comment */
fraglimit	15
type		"single ffa lms tourney"
}
{ map "ctf_gate1" longname "" type "ctf, dom, dd" }
)",
                                     "scripts/arenas.txt", warnings);
  EXPECT_TRUE(warnings.empty());
  ASSERT_EQ(infos.size(), 2u);
  EXPECT_EQ(infos[0].get("map").value_or(""), "oa_rpg3dm2");
  EXPECT_EQ(infos[0].get("FRAGLIMIT").value_or(""), "15");   // keys are case-insensitive
  EXPECT_EQ(infos[0].get("type").value_or(""), "single ffa lms tourney");
  EXPECT_FALSE(infos[0].get("bots").has_value());
  // One line holding the whole block; an empty value reads as the game's "<NULL>".
  EXPECT_EQ(infos[1].get("longname").value_or(""), "<NULL>");
  EXPECT_EQ(infos[1].get("type").value_or(""), "ctf, dom, dd");
}

TEST(ArenaInfo, AStrayBraceIsAKeyLikeInTheGame) {
  // z_oacmp-volume1-v3's oacmpv1.arena: a "{" opens a block and the next "{" is read as a key
  // whose value (the rest of its line) is empty; the block still holds its map.
  std::vector<std::string> warnings;
  const auto infos = parseArenaInfos("{ map \"oacmpdm4\" }\n{\n//DM05\n{\nmap \"oacmpdm5\"\ntype \"ffa lms\"\n}\n",
                                     "scripts/oacmpv1.arena", warnings);
  EXPECT_TRUE(warnings.empty());
  ASSERT_EQ(infos.size(), 2u);
  EXPECT_EQ(infos[1].get("{").value_or(""), "<NULL>");
  EXPECT_EQ(infos[1].get("map").value_or(""), "oacmpdm5");
}

TEST(ArenaInfo, ValueIsOnTheKeysLineAndARepeatedKeyReplaces) {
  std::vector<std::string> warnings;
  const auto infos = parseArenaInfos("{\nmap\n\"oa_dm1\"\ntype \"ffa\" type \"ctf\"\n}", "a.arena", warnings);
  ASSERT_EQ(infos.size(), 1u);
  // "map" has no value on its line: "<NULL>"; "oa_dm1" is then a key, its value the next token on that line (none).
  EXPECT_EQ(infos[0].get("map").value_or(""), "<NULL>");
  EXPECT_EQ(infos[0].get("oa_dm1").value_or(""), "<NULL>");
  EXPECT_EQ(infos[0].get("type").value_or(""), "ctf");
  EXPECT_EQ(infos[0].keys.size(), 3u);
}

TEST(ArenaInfo, MalformedTextWarnsWithFileAndLineAndKeepsWhatWasRead) {
  std::vector<std::string> warnings;
  auto infos = parseArenaInfos("{ map \"a\" }\nmap \"b\"\n{ map \"c\" }", "x.arena", warnings);
  ASSERT_EQ(infos.size(), 1u);   // the game stops at a block without '{'
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("x.arena:2: expected '{'"), std::string::npos) << warnings[0];

  warnings.clear();
  infos = parseArenaInfos("{ map \"a\"\n  type \"ffa", "y.arena", warnings);   // unclosed quote and block
  ASSERT_EQ(infos.size(), 1u);
  EXPECT_EQ(infos[0].get("type").value_or(""), "ffa");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("not closed"), std::string::npos) << warnings[0];

  warnings.clear();
  infos = parseArenaInfos("{ map \"a;b\" longname \"ok\" }", "z.arena", warnings);   // ';' cannot be stored
  ASSERT_EQ(infos.size(), 1u);
  EXPECT_FALSE(infos[0].get("map").has_value());
  EXPECT_EQ(infos[0].get("longname").value_or(""), "ok");
  EXPECT_EQ(warnings.size(), 1u);

  warnings.clear();
  EXPECT_TRUE(parseArenaInfos("", "empty.arena", warnings).empty());
  EXPECT_TRUE(parseArenaInfos("// only a comment\n/* unterminated", "c.arena", warnings).empty());
  EXPECT_TRUE(warnings.empty());
}

TEST(ArenaInfo, LimitsCutBlocksKeysAndTokens) {
  ArenaParseLimits limits;
  limits.maxBlocks = 2;
  limits.maxKeysPerBlock = 2;
  limits.maxTokenLength = 8;
  std::vector<std::string> warnings;
  const auto infos = parseArenaInfos("{ a 1 }\n{ map \"averyveryverylongname\"\nb 2\nc 3 }\n{ d 4 }", "l.arena",
                                     warnings, limits);
  ASSERT_EQ(infos.size(), 2u);
  EXPECT_EQ(infos[1].get("map").value_or(""), "averyver");
  EXPECT_EQ(infos[1].keys.size(), 2u);
  EXPECT_FALSE(infos[1].get("c").has_value());
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("l.arena:4: more than 2 keys"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("l.arena:5: more than 2 blocks"), std::string::npos) << warnings[1];
}

TEST(ArenaInfo, RandomBytesNeverCrash) {
  std::mt19937 random(7);
  const std::string alphabet = "{}\"/*\n \t,;\\abc\0\xff";
  for (int round = 0; round < 2000; ++round) {
    std::string text(random() % 64, ' ');
    for (char& c : text) c = alphabet[random() % alphabet.size()];
    std::vector<std::string> warnings;
    const auto infos = parseArenaInfos(text, "fuzz.arena", warnings);
    EXPECT_LE(infos.size(), text.size());
    ArenaIndex index;
    index.addFile(text, "fuzz.arena", warnings);
  }
}

TEST(ArenaInfo, GameTypesAndTheirSpawnFamilies) {
  EXPECT_EQ(splitGameTypes("ctf, dom,dd\tOneFlag "), (std::vector<std::string>{"ctf", "dom", "dd", "oneflag"}));
  EXPECT_TRUE(splitGameTypes(" , ").empty());
  for (const char* team : {"ctf", "oneflag", "1fctf", "overload", "obelisk", "harvester", "elimination",
                           "ctfelimination", "ctfelim", "CTF"})
    EXPECT_EQ(spawnFamilyOfGameType(team), SpawnFamily::Team) << team;
  for (const char* dm : {"single", "ffa", "tourney", "team", "tdm", "lms", "dom", "dd", "pos"})
    EXPECT_EQ(spawnFamilyOfGameType(dm), SpawnFamily::Deathmatch) << dm;
  EXPECT_FALSE(spawnFamilyOfGameType("ctfx").has_value());
  EXPECT_FALSE(spawnFamilyOfGameType("").has_value());
}

TEST(ArenaInfo, IndexKeepsEachMapsFirstEntryAndItsFirstKnownGameType) {
  ArenaIndex index;
  std::vector<std::string> warnings;
  index.addFile("{ map \"oa_ctf4ish\" type \"ctf elimination ctfelimination dd\" }\n"
                "{ map \"OA_DM1\" type \"<weird> ffa ctf\" }\n{ map \"nomode\" }\n{ type \"ctf\" }",
                "scripts/arenas.txt", warnings);
  index.addFile("{ map \"oa_ctf4ish\" type \"ffa\" }\n{ map \"extra\" type \"harvester\" }", "scripts/b.arena",
                warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(index.size(), 4u);
  const ArenaEntry* ctf = index.find("oa_ctf4ish");
  ASSERT_NE(ctf, nullptr);
  EXPECT_EQ(ctf->file, "scripts/arenas.txt");   // the first entry wins
  EXPECT_EQ(ctf->gameType, "ctf");
  EXPECT_EQ(ctf->family, SpawnFamily::Team);
  const ArenaEntry* dm1 = index.find("oa_dm1");   // case-insensitive; an unknown word is skipped
  ASSERT_NE(dm1, nullptr);
  EXPECT_EQ(dm1->gameType, "ffa");
  EXPECT_EQ(dm1->family, SpawnFamily::Deathmatch);
  ASSERT_NE(index.find("nomode"), nullptr);
  EXPECT_FALSE(index.find("nomode")->family.has_value());
  EXPECT_EQ(index.find("extra")->family, SpawnFamily::Team);
  EXPECT_EQ(index.find("missing"), nullptr);
}

}  // namespace
}  // namespace pa::allmaps
