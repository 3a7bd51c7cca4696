// libFuzzer: archive bytes -> GameFileSystem (physfs mount from memory), listing, lookups, reads.
// Acceptable outcomes: the archive is refused (mountErrors) or an entry throws FormatError.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/vfs/game_filesystem.h"

namespace {

/// Aborts (a libFuzzer crash) when an invariant of the VFS does not hold.
void require(bool condition) {
  if (!condition) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<q3::GameFileSystem::MemoryArchive> archives(1);
  archives[0].name = "fuzz.pk3";
  archives[0].bytes.assign(reinterpret_cast<const std::byte*>(data), reinterpret_cast<const std::byte*>(data) + size);
  const q3::GameFileSystem fs(std::move(archives));
  require(fs.archives().size() + fs.mountErrors().size() == 1);

  const std::vector<std::string> files = fs.allFiles();
  require(files.size() == fs.archiveFileCount());
  size_t readBytes = 0;
  for (const std::string& path : files) {
    const bool found = fs.exists(path);
    require(found && !fs.sourceOf(path).empty());  // every listed file can be looked up
    try {
      const auto bytes = fs.readFile(path);
      require(bytes.has_value());
      if (bytes) readBytes += bytes->size();
    } catch (const q3::FormatError&) {
      // A corrupt entry (bad deflate stream, CRC, truncated data): refused with a message.
    }
  }
  for (const char* dir : {"", "scripts", "maps", "models/players/x", "textures"})
    for (const char* extension : {"", ".shader", ".bsp", ".tga"}) (void)fs.listFiles(dir, extension);
  for (const char* path : {"scripts/a.shader", "../x", "/etc/passwd", "a\\b", "maps//x.bsp"}) {
    try {
      (void)fs.readFile(path);
    } catch (const q3::FormatError&) {
    }
  }
  (void)readBytes;
  return 0;
}
