#pragma once
// A Quake III game folder as the engine sees it: *.pk3 archives plus loose files.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace q3 {

/// Read-only view of a game folder (e.g. /usr/share/games/openarena/baseoa), with the search
/// order of ioquake3's FS_AddGameDirectory:
///  - every `*.pk3` of the folder, sorted with the engine's FS_PathCmp (case-insensitive);
///    a later archive overrides an earlier one (pak1 over pak0);
///  - loose files in the folder override every archive.
/// Lookups inside archives are case-insensitive (the engine hashes lower-cased names and
/// compares with FS_FilenameCompare); loose files are looked up case-sensitively, as the
/// engine's fopen does on Linux. '\\' reads as '/'. Paths with ".." or a leading '/' are refused.
///
/// Archives are read through physfs, a library with process-wide state: init/deinit are
/// reference-counted and each archive is mounted once at a private mount point, so several
/// GameFileSystem objects (and threads reading) can coexist. physfs's own search order is not
/// used: the override order above is ours. Archives are hostile input: one that would make
/// physfs 3.0.2 abort (a zip64 locator pointing past its record) is refused like a corrupt one.
class GameFileSystem {
 public:
  /// An archive held in memory: the name that archives() and sourceOf() report, and its bytes.
  struct MemoryArchive {
    std::string name;
    std::vector<std::byte> bytes;
  };


  /// Mounts `gameDir`. Throws std::runtime_error if it is not a readable folder; an archive
  /// that physfs cannot open is skipped and named in mountErrors().
  explicit GameFileSystem(const std::filesystem::path& gameDir);
  /// Mounts in-memory archives, lowest priority first, with no loose files (tests, fuzzing).
  /// An archive that physfs cannot open is skipped and named in mountErrors().
  explicit GameFileSystem(std::vector<MemoryArchive> archives);
  ~GameFileSystem();
  GameFileSystem(const GameFileSystem&) = delete;
  GameFileSystem& operator=(const GameFileSystem&) = delete;

  /// Contents of a game path (e.g. "scripts/base.shader"); nullopt if it does not exist.
  /// Throws FormatError if the entry exists but cannot be read (corrupt archive) or is over 256 MiB.
  std::optional<std::vector<std::byte>> readFile(std::string_view path) const;
  /// True if readFile(path) would find something.
  bool exists(std::string_view path) const;
  /// Files directly inside `dir` whose name ends with `extension` (case-insensitive; "" = all),
  /// as game paths ("scripts/base.shader"), each once (the overriding copy), sorted with FS_PathCmp.
  std::vector<std::string> listFiles(std::string_view dir, std::string_view extension) const;
  /// Every visible file (archives and loose files, recursively; not the top-level *.pk3 files),
  /// each once, sorted with FS_PathCmp.
  std::vector<std::string> allFiles() const;
  /// Where a path is read from: the archive file name, "(loose)" or "" when missing.
  std::string sourceOf(std::string_view path) const;

  /// Mounted archives, lowest priority first.
  const std::vector<std::filesystem::path>& archives() const { return archives_; }
  /// Archives that could not be mounted, with the reason.
  const std::vector<std::string>& mountErrors() const { return mountErrors_; }
  /// Number of distinct files visible in archives.
  size_t archiveFileCount() const { return index_.size(); }

 private:
  struct Entry {
    size_t archive = 0;     ///< index into archives_/mountPoints_
    std::string innerPath;  ///< path inside the archive, original case
  };
  std::optional<std::filesystem::path> loosePath(std::string_view path) const;
  void indexArchive(size_t archive);

  std::filesystem::path root_;  ///< empty for in-memory archives: no loose files
  std::vector<std::filesystem::path> archives_;
  std::vector<std::string> mountKeys_;    ///< physfs's name of each mount (to unmount it)
  std::vector<std::string> mountPoints_;
  std::vector<std::vector<std::byte>> memoryBytes_;  ///< bytes of in-memory archives, kept while mounted
  std::vector<std::string> mountErrors_;
  std::unordered_map<std::string, Entry> index_;  ///< key: lower-cased game path
};

/// Normalises a game path: '\\' -> '/', duplicate slashes removed; nullopt if it is absolute,
/// empty or contains a ".." component.
std::optional<std::string> normalizeGamePath(std::string_view path);

}  // namespace q3
