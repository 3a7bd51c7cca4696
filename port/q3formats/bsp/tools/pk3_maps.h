#pragma once
// Reads .bsp files out of .pk3 archives with physfs, for the stats tool and the real-data test.
// (The game file system proper lives in q3_vfs; this only lists and reads one archive at a time.)
#include <physfs.h>

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace q3::tools {

/// Initialises physfs once for the process; mounts one archive at a time.
class Pk3Reader {
 public:
  explicit Pk3Reader(const char* argv0) {
    if (!PHYSFS_isInit() && !PHYSFS_init(argv0)) throw std::runtime_error("PHYSFS_init failed");
  }
  Pk3Reader(const Pk3Reader&) = delete;
  Pk3Reader& operator=(const Pk3Reader&) = delete;
  ~Pk3Reader() {
    unmount();
    PHYSFS_deinit();
  }

  /// Mounts `archive` (replacing the previous one); throws if physfs cannot open it.
  void mount(const std::string& archive) {
    unmount();
    if (!PHYSFS_mount(archive.c_str(), nullptr, 0))
      throw std::runtime_error("cannot open " + archive + ": " +
                               PHYSFS_getErrorByCode(PHYSFS_getLastErrorCode()));
    mounted_ = archive;
  }

  /// Paths "maps/NAME.bsp" in the mounted archive, sorted.
  std::vector<std::string> listMaps() const {
    std::vector<std::string> maps;
    char** files = PHYSFS_enumerateFiles("maps");
    for (char** f = files; f && *f; ++f) {
      const std::string name = *f;
      if (name.size() > 4 && (name.ends_with(".bsp") || name.ends_with(".BSP"))) maps.push_back("maps/" + name);
    }
    PHYSFS_freeList(files);
    std::sort(maps.begin(), maps.end());
    return maps;
  }

  /// Whole file from the mounted archive.
  std::vector<std::byte> read(const std::string& path) const {
    PHYSFS_File* file = PHYSFS_openRead(path.c_str());
    if (!file) throw std::runtime_error("cannot open " + mounted_ + ":" + path);
    const PHYSFS_sint64 length = PHYSFS_fileLength(file);
    std::vector<std::byte> bytes(length > 0 ? static_cast<size_t>(length) : 0);
    const PHYSFS_sint64 got = PHYSFS_readBytes(file, bytes.data(), bytes.size());
    PHYSFS_close(file);
    if (got != static_cast<PHYSFS_sint64>(bytes.size())) throw std::runtime_error("short read of " + path);
    return bytes;
  }

 private:
  void unmount() {
    if (!mounted_.empty()) PHYSFS_unmount(mounted_.c_str());
    mounted_.clear();
  }
  std::string mounted_;
};

/// The OpenArena archives that contain maps, if installed.
inline std::vector<std::string> openArenaMapArchives(const std::string& baseoa = "/usr/share/games/openarena/baseoa") {
  std::vector<std::string> out;
  for (const char* name : {"pak1-maps.pk3", "pak6-patch085.pk3", "pak6-patch088.pk3", "z_oacmp-volume1-v3.pk3"}) {
    const std::string path = baseoa + "/" + name;
    if (FILE* f = std::fopen(path.c_str(), "rb")) {
      std::fclose(f);
      out.push_back(path);
    }
  }
  return out;
}

}  // namespace q3::tools
