#include "port/q3formats/vfs/game_filesystem.h"

#include <gtest/gtest.h>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/vfs/tests/stored_zip.h"

namespace {

std::string text(const std::optional<std::vector<std::byte>>& bytes) {
  if (!bytes) return "<missing>";
  return std::string(reinterpret_cast<const char*>(bytes->data()), bytes->size());
}

void writeLoose(const std::filesystem::path& file, const std::string& data) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << data;
}

TEST(GameFileSystem, LaterArchiveOverridesEarlierAndLooseOverridesAll) {
  q3::test::TempDir dir("vfs_order");
  // Engine order (FS_PathCmp, case-insensitive): pak0 < PAK1 < z_extra, so z_extra wins.
  q3::test::writeStoredZip(dir.path() / "pak0.pk3", {{"scripts/a.shader", "from pak0"},
                                                     {"textures/Wall.tga", "wall pak0"},
                                                     {"only0.txt", "zero"}});
  q3::test::writeStoredZip(dir.path() / "PAK1.pk3", {{"scripts/a.shader", "from pak1"},
                                                     {"textures/wall.TGA", "wall pak1"}});
  q3::test::writeStoredZip(dir.path() / "z_extra.pk3", {{"scripts/a.shader", "from z_extra"}});
  writeLoose(dir.path() / "textures/wall.TGA", "wall loose");

  q3::GameFileSystem fs(dir.path());
  ASSERT_EQ(fs.archives().size(), 3u);
  EXPECT_EQ(fs.archives()[0].filename(), "pak0.pk3");
  EXPECT_EQ(fs.archives()[1].filename(), "PAK1.pk3");
  EXPECT_EQ(fs.archives()[2].filename(), "z_extra.pk3");
  EXPECT_EQ(text(fs.readFile("scripts/a.shader")), "from z_extra");
  EXPECT_EQ(fs.sourceOf("scripts/a.shader"), "z_extra.pk3");
  EXPECT_EQ(text(fs.readFile("only0.txt")), "zero");
  // Archive lookups ignore case; the loose file is found only with its exact case.
  EXPECT_EQ(text(fs.readFile("textures/wall.TGA")), "wall loose");
  EXPECT_EQ(fs.sourceOf("textures/wall.TGA"), "(loose)");
  EXPECT_EQ(text(fs.readFile("TEXTURES/WALL.tga")), "wall pak1");
  EXPECT_EQ(text(fs.readFile("textures\\wall.tga")), "wall pak1");
  EXPECT_FALSE(fs.readFile("missing.txt"));
  EXPECT_FALSE(fs.exists("missing.txt"));
  EXPECT_TRUE(fs.exists("Only0.TXT"));
}

TEST(GameFileSystem, ListsDirectChildrenOnceSortedLikeTheEngine) {
  q3::test::TempDir dir("vfs_list");
  q3::test::writeStoredZip(dir.path() / "pak0.pk3", {{"scripts/b.shader", "b"},
                                                     {"scripts/A.shader", "a"},
                                                     {"scripts/sub/c.shader", "c"},
                                                     {"scripts/readme.txt", "x"}});
  q3::test::writeStoredZip(dir.path() / "pak1.pk3", {{"scripts/b.shader", "b2"}});
  writeLoose(dir.path() / "scripts/loose.SHADER", "l");
  q3::GameFileSystem fs(dir.path());
  const auto list = fs.listFiles("scripts", ".shader");
  ASSERT_EQ(list.size(), 3u);
  EXPECT_EQ(list[0], "scripts/A.shader");
  EXPECT_EQ(list[1], "scripts/b.shader");
  EXPECT_EQ(list[2], "scripts/loose.SHADER");
  EXPECT_EQ(fs.listFiles("scripts", "").size(), 4u);
  const auto all = fs.allFiles();
  ASSERT_EQ(all.size(), 5u);
  EXPECT_EQ(all[2], "scripts/loose.SHADER");
  EXPECT_EQ(all[3], "scripts/readme.txt");
  EXPECT_EQ(all[4], "scripts/sub/c.shader");
}

TEST(GameFileSystem, RefusesEscapingPaths) {
  q3::test::TempDir dir("vfs_escape");
  writeLoose(dir.path() / "inside.txt", "in");
  writeLoose(dir.path().parent_path() / "patharena_outside_secret.txt", "secret");
  q3::GameFileSystem fs(dir.path());
  EXPECT_FALSE(fs.readFile("../patharena_outside_secret.txt"));
  EXPECT_FALSE(fs.readFile("/etc/passwd"));
  EXPECT_FALSE(fs.readFile("a/../../x"));
  EXPECT_EQ(text(fs.readFile("inside.txt")), "in");
  std::filesystem::remove(dir.path().parent_path() / "patharena_outside_secret.txt");
  EXPECT_EQ(q3::normalizeGamePath("a\\\\b//c/"), "a/b/c");
  EXPECT_FALSE(q3::normalizeGamePath(""));
}

TEST(GameFileSystem, SkipsCorruptArchiveAndSharesMountsBetweenInstances) {
  q3::test::TempDir dir("vfs_bad");
  writeLoose(dir.path() / "broken.pk3", "this is not a zip file");
  q3::test::writeStoredZip(dir.path() / "good.pk3", {{"x.txt", "x"}});
  {
    q3::GameFileSystem first(dir.path());
    EXPECT_EQ(first.archives().size(), 1u);
    ASSERT_EQ(first.mountErrors().size(), 1u);
    EXPECT_NE(first.mountErrors()[0].find("broken.pk3"), std::string::npos);
    {
      q3::GameFileSystem second(dir.path());
      EXPECT_EQ(text(second.readFile("x.txt")), "x");
    }
    EXPECT_EQ(text(first.readFile("x.txt")), "x");  // still mounted after the other went away
  }
  q3::GameFileSystem again(dir.path());  // physfs de-initialised and initialised again
  EXPECT_EQ(text(again.readFile("x.txt")), "x");
}

std::vector<std::byte> bytesOf(const std::string& s) {
  const auto* p = reinterpret_cast<const std::byte*>(s.data());
  return {p, p + s.size()};
}

TEST(GameFileSystem, MountsArchivesFromMemoryWithoutLooseFiles) {
  std::vector<q3::GameFileSystem::MemoryArchive> archives;
  archives.push_back({"pak0.pk3", bytesOf(q3::test::storedZip({{"scripts/a.shader", "old"}, {"Maps/X.bsp", "m"}}))});
  archives.push_back({"junk.pk3", bytesOf("not a zip")});
  archives.push_back({"pak1.pk3", bytesOf(q3::test::storedZip({{"scripts/a.shader", "new"}}))});
  q3::GameFileSystem fs(std::move(archives));
  ASSERT_EQ(fs.archives().size(), 2u);
  ASSERT_EQ(fs.mountErrors().size(), 1u);
  EXPECT_NE(fs.mountErrors()[0].find("junk.pk3"), std::string::npos);
  EXPECT_EQ(text(fs.readFile("scripts/a.shader")), "new");
  EXPECT_EQ(fs.sourceOf("scripts/a.shader"), "pak1.pk3");
  EXPECT_EQ(text(fs.readFile("maps/x.bsp")), "m");
  EXPECT_EQ(fs.allFiles(), (std::vector<std::string>{"Maps/X.bsp", "scripts/a.shader"}));
  EXPECT_EQ(fs.listFiles("", ""), std::vector<std::string>{});  // nothing loose at the top
  EXPECT_FALSE(fs.exists("CMakeLists.txt"));  // never the working directory
}

/// A zip whose zip64 locator gives a record offset past the record physfs finds before the
/// locator: physfs 3.0.2 asserts (aborts the game) on it, so the VFS must refuse it first.
std::string zip64LocatorPastItsRecord() {
  const std::string zip = q3::test::storedZip({{"maps/x.bsp", "IBSP"}});
  std::string out = zip.substr(0, zip.size() - 22);  // everything before the end record
  auto u32 = [&out](uint32_t v) { for (int i = 0; i < 4; ++i) out.push_back(char((v >> (8 * i)) & 0xFF)); };
  const uint32_t record = static_cast<uint32_t>(out.size());
  u32(0x06064b50);                                      // zip64 end of central directory, 56 bytes
  out.append(52, '\0');
  u32(0x07064b50), u32(0), u32(record + 1), u32(0), u32(1);  // locator: offset one byte past the record
  return out + zip.substr(zip.size() - 22);             // the original end record
}

TEST(GameFileSystem, RefusesZip64LocatorPastItsRecordInMemoryAndOnDisk) {
  const std::string hostile = zip64LocatorPastItsRecord();
  std::vector<q3::GameFileSystem::MemoryArchive> archives;
  archives.push_back({"hostile.pk3", bytesOf(hostile)});
  q3::GameFileSystem memory(std::move(archives));
  EXPECT_TRUE(memory.archives().empty());
  ASSERT_EQ(memory.mountErrors().size(), 1u);
  EXPECT_NE(memory.mountErrors()[0].find("zip64"), std::string::npos) << memory.mountErrors()[0];

  q3::test::TempDir dir("vfs_zip64");
  writeLoose(dir.path() / "hostile.pk3", hostile);
  q3::test::writeStoredZip(dir.path() / "good.pk3", {{"x.txt", "x"}});
  q3::GameFileSystem disk(dir.path());
  ASSERT_EQ(disk.mountErrors().size(), 1u);
  EXPECT_NE(disk.mountErrors()[0].find("hostile.pk3: zip64"), std::string::npos) << disk.mountErrors()[0];
  EXPECT_EQ(text(disk.readFile("x.txt")), "x");
}

TEST(GameFileSystem, RefusesZip64LocatorAtTheStart) {
  // An end record right after a zip64 locator at byte 0: physfs 3.0.2 asserts on it.
  std::string bytes;
  auto u32 = [&bytes](uint32_t v) { for (int i = 0; i < 4; ++i) bytes.push_back(char((v >> (8 * i)) & 0xFF)); };
  u32(0x07064b50), u32(0), u32(0), u32(0), u32(1);  // locator: disk 0, record at 0, 1 disk
  u32(0x06054b50), u32(0), u32(0), u32(0), u32(0);  // end record, no entries
  bytes.append(2, '\0');                            // comment length
  std::vector<q3::GameFileSystem::MemoryArchive> archives;
  archives.push_back({"hostile.pk3", bytesOf(bytes)});
  q3::GameFileSystem fs(std::move(archives));
  ASSERT_EQ(fs.mountErrors().size(), 1u);
  EXPECT_NE(fs.mountErrors()[0].find("locator at the start"), std::string::npos) << fs.mountErrors()[0];
}

TEST(GameFileSystem, DoubleSlashEntryDoesNotLoopForever) {
  // physfs lists an empty name inside "dir" for "dir//x.cfg"; following it would never end.
  std::vector<q3::GameFileSystem::MemoryArchive> archives;
  archives.push_back({"pak0.pk3", bytesOf(q3::test::storedZip({{"dir//x.cfg", "d"}, {"maps/x.bsp", "m"}}))});
  q3::GameFileSystem fs(std::move(archives));
  EXPECT_EQ(fs.allFiles(), std::vector<std::string>{"maps/x.bsp"});
  EXPECT_EQ(text(fs.readFile("maps/x.bsp")), "m");
}

TEST(GameFileSystem, SymlinkEntryClaimingGigabytesIsLeftOut) {
  // A Unix symlink entry whose central directory claims a 4 GiB target: physfs 3.0.2 allocated
  // the claimed size while listing the archive (q3_fuzz_pk3, a 316-byte pk3). Its allocations are
  // now capped: the link does not resolve, physfs then fails to list the link's folder (so its
  // siblings are not indexed either), and the archive's other folders still work.
  std::string zip = q3::test::storedZip({{"scripts/x.shader", "x"}, {"maps/link.bsp", "maps/x.bsp"}, {"maps/x.bsp", "IBSP"}});
  const size_t central = zip.rfind("maps/link.bsp") - 46;  // its central directory header
  ASSERT_EQ(zip.compare(central, 4, "PK\x01\x02"), 0);
  auto put16 = [&zip](size_t at, uint16_t v) { zip[at] = char(v & 0xFF), zip[at + 1] = char(v >> 8); };
  auto put32 = [&](size_t at, uint32_t v) { put16(at, uint16_t(v & 0xFFFF)), put16(at + 2, uint16_t(v >> 16)); };
  put16(central + 4, 0x031e);        // made by Unix: physfs honours the file type bits
  put32(central + 24, 0xFA16B031u);  // uncompressed size: about 4 GiB
  put32(central + 38, 0xA1FF0000u);  // external attributes: S_IFLNK | 0777
  std::vector<q3::GameFileSystem::MemoryArchive> archives;
  archives.push_back({"links.pk3", bytesOf(zip)});
  q3::GameFileSystem fs(std::move(archives));
  EXPECT_TRUE(fs.mountErrors().empty());
  EXPECT_EQ(fs.allFiles(), std::vector<std::string>{"scripts/x.shader"});
  EXPECT_EQ(text(fs.readFile("scripts/x.shader")), "x");
  EXPECT_FALSE(fs.readFile("maps/link.bsp").has_value());
}

TEST(GameFileSystem, MissingFolderThrows) {
  EXPECT_THROW(q3::GameFileSystem("/nonexistent/patharena/folder"), std::runtime_error);
}

TEST(GameFileSystem, RealOpenArenaData) {
  const std::filesystem::path base = "/usr/share/games/openarena/baseoa";
  if (!std::filesystem::exists(base / "pak0.pk3")) GTEST_SKIP() << "OpenArena data not installed";
  q3::GameFileSystem fs(base);
  EXPECT_TRUE(fs.mountErrors().empty());
  // Every archive the installed packages put there is mounted (9 with Debian 12's openarena-data
  // packages; more where extra map packs are installed).
  size_t archivesPresent = 0;
  for (const auto& entry : std::filesystem::directory_iterator(base))
    archivesPresent += entry.path().extension() == ".pk3";
  EXPECT_GE(archivesPresent, 9u);
  EXPECT_EQ(fs.archives().size(), archivesPresent);
  EXPECT_GT(fs.archiveFileCount(), 1000u);
  EXPECT_FALSE(fs.listFiles("scripts", ".shader").empty());
  EXPECT_TRUE(fs.exists("maps/oa_dm1.bsp"));
  auto demo = fs.readFile("demos/demo088-test1.dm_71");
  ASSERT_TRUE(demo);
  EXPECT_GT(demo->size(), 1000u);
}

}  // namespace
