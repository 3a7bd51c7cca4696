#include "port/q3formats/vfs/game_filesystem.h"

#include <physfs.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <stdexcept>
#include <system_error>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/common/tokenizer.h"

namespace q3 {
namespace {

constexpr size_t kMaxFileBytes = size_t{1} << 28;  // 256 MiB: larger entries (zip bombs) are refused
constexpr long kMaxFolderDepth = 64;               // deeper folders of an archive are not indexed

std::string physfsError() {
  return PHYSFS_getErrorByCode(PHYSFS_getLastErrorCode());
}

uint32_t le32(const unsigned char* p) {
  return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
}

/// Reads `n` bytes at `offset` of an archive; false when they are not all there.
using ReadAt = std::function<bool(uint64_t offset, unsigned char* out, size_t n)>;

/// physfs 3.0.2 aborts the process (asserts left on in Debian's build) on a zip64 "end of
/// central directory locator" at the very start of the file, or whose record offset lies after
/// the record that physfs then finds 56 or 84 bytes before the locator. Returns why an archive
/// is such a zip, or nullopt.
/// Every end-of-central-directory signature in the last 64 KiB is checked, whichever physfs picks.
std::optional<std::string> physfsZip64Hazard(uint64_t size, const ReadAt& readAt) {
  constexpr uint32_t kEnd = 0x06054b50, kLocator = 0x07064b50, kZip64End = 0x06064b50;
  const uint64_t start = size > 0xFFFF + 22 ? size - (0xFFFF + 22) : 0;
  std::vector<unsigned char> tail(static_cast<size_t>(size - start));
  if (tail.size() < 4 || !readAt(start, tail.data(), tail.size())) return std::nullopt;
  auto signatureAt = [&readAt](uint64_t offset, uint32_t signature) {
    unsigned char b[4];
    return readAt(offset, b, 4) && le32(b) == signature;
  };
  for (size_t i = tail.size() - 4 + 1; i-- > 0;) {
    if (le32(&tail[i]) != kEnd || start + i < 20) continue;
    const uint64_t locator = start + i - 20;
    unsigned char offsetBytes[8];
    if (!signatureAt(locator, kLocator)) continue;
    if (locator == 0) return std::string("zip64 end of central directory locator at the start of the file");
    if (!readAt(locator + 8, offsetBytes, 8)) continue;
    const uint64_t recordOffset = le32(offsetBytes) | uint64_t{le32(offsetBytes + 4)} << 32;
    if (signatureAt(recordOffset, kZip64End)) continue;  // physfs uses the record at the offset
    for (uint64_t back : {56u, 84u}) {
      if (locator <= back || !signatureAt(locator - back, kZip64End)) continue;
      if (locator - back < recordOffset)
        return "zip64 end of central directory at byte " + std::to_string(locator - back) +
               " lies before the offset its locator gives (" + std::to_string(recordOffset) + ")";
      break;
    }
  }
  return std::nullopt;
}

std::optional<std::string> physfsZip64Hazard(const std::vector<std::byte>& bytes) {
  return physfsZip64Hazard(bytes.size(), [&bytes](uint64_t offset, unsigned char* out, size_t n) {
    if (offset > bytes.size() || n > bytes.size() - offset) return false;
    std::memcpy(out, bytes.data() + offset, n);
    return true;
  });
}

std::optional<std::string> physfsZip64Hazard(const std::filesystem::path& archive) {
  std::ifstream in(archive, std::ios::binary);
  std::error_code ec;
  const uint64_t size = std::filesystem::file_size(archive, ec);
  if (!in || ec) return std::nullopt;  // physfs reports the unreadable file itself
  return physfsZip64Hazard(size, [&in, size](uint64_t offset, unsigned char* out, size_t n) {
    if (offset > size || n > size - offset) return false;
    in.clear();
    in.seekg(static_cast<std::streamoff>(offset));
    return static_cast<bool>(in.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(n)));
  });
}

/// A read-only PHYSFS_Io over bytes that outlive it. (physfs 3.0.2's PHYSFS_mountMemory leaks
/// its own memory Io, 128 bytes per mount, so in-memory archives are mounted through this one.)
struct ByteIo {
  const std::byte* data = nullptr;
  uint64_t size = 0;
  uint64_t position = 0;
};

ByteIo& byteIo(PHYSFS_Io* io) { return *static_cast<ByteIo*>(io->opaque); }

PHYSFS_Io* createByteIo(const std::byte* data, uint64_t size) {
  auto* io = new PHYSFS_Io{};
  io->version = 0;
  io->opaque = new ByteIo{data, size, 0};
  io->read = [](PHYSFS_Io* self, void* buffer, PHYSFS_uint64 length) -> PHYSFS_sint64 {
    ByteIo& state = byteIo(self);
    const uint64_t n = std::min<uint64_t>(length, state.size - state.position);
    if (n) std::memcpy(buffer, state.data + state.position, n);
    state.position += n;
    return static_cast<PHYSFS_sint64>(n);
  };
  io->write = [](PHYSFS_Io*, const void*, PHYSFS_uint64) -> PHYSFS_sint64 {
    PHYSFS_setErrorCode(PHYSFS_ERR_READ_ONLY);
    return -1;
  };
  io->seek = [](PHYSFS_Io* self, PHYSFS_uint64 offset) -> int {
    ByteIo& state = byteIo(self);
    if (offset > state.size) {
      PHYSFS_setErrorCode(PHYSFS_ERR_PAST_EOF);
      return 0;
    }
    state.position = offset;
    return 1;
  };
  io->tell = [](PHYSFS_Io* self) -> PHYSFS_sint64 { return static_cast<PHYSFS_sint64>(byteIo(self).position); };
  io->length = [](PHYSFS_Io* self) -> PHYSFS_sint64 { return static_cast<PHYSFS_sint64>(byteIo(self).size); };
  io->duplicate = [](PHYSFS_Io* self) -> PHYSFS_Io* { return createByteIo(byteIo(self).data, byteIo(self).size); };
  io->flush = [](PHYSFS_Io*) -> int { return 1; };
  io->destroy = [](PHYSFS_Io* self) {
    delete static_cast<ByteIo*>(self->opaque);
    delete self;
  };
  return io;
}

/// physfs's allocations are refused beyond this size. physfs 3.0.2 allocates a zip symlink's
/// target at the size its entry claims (up to 4 GiB) and inflates into it: a 316-byte pk3
/// claiming a 4 GiB symlink made physfs allocate 4 GiB while listing it (q3_fuzz_pk3); a deflate
/// bomb would also fill it. The target then fails to resolve and the entry is left out. Real
/// archives need a few MiB at most (the entry table of a large pk3).
constexpr PHYSFS_uint64 kMaxPhysfsAllocation = PHYSFS_uint64{64} << 20;

/// The allocator handed to physfs: malloc and friends, with kMaxPhysfsAllocation.
const PHYSFS_Allocator kCappedAllocator = {
    nullptr, nullptr,
    [](PHYSFS_uint64 size) -> void* { return size <= kMaxPhysfsAllocation ? std::malloc(static_cast<size_t>(size)) : nullptr; },
    [](void* block, PHYSFS_uint64 size) -> void* {
      return size <= kMaxPhysfsAllocation ? std::realloc(block, static_cast<size_t>(size)) : nullptr;
    },
    [](void* block) { std::free(block); }};

/// Initialises physfs with the capped allocator; throws on failure.
void initPhysfs() {
  if (!PHYSFS_setAllocator(&kCappedAllocator) || !PHYSFS_init(nullptr))
    throw std::runtime_error("physfs init failed: " + physfsError());
}

/// Process-wide physfs state: reference-counted init and one mount per archive file.
class PhysfsRegistry {
 public:
  static PhysfsRegistry& instance() {
    static PhysfsRegistry registry;
    return registry;
  }

  /// Mounts an archive (or reuses its mount); returns the mount point or throws.
  std::string acquire(const std::string& archive) {
    std::lock_guard lock(mutex_);
    if (users_ == 0 && !PHYSFS_isInit()) initPhysfs();
    ++users_;
    auto it = mounts_.find(archive);
    if (it != mounts_.end()) {
      ++it->second.refs;
      return it->second.mountPoint;
    }
    const std::string mountPoint = "patharena_vfs/" + std::to_string(nextId_++);
    if (auto hazard = physfsZip64Hazard(std::filesystem::path(archive))) {
      releaseUserLocked();
      throw std::runtime_error(*hazard);
    }
    if (!PHYSFS_mount(archive.c_str(), mountPoint.c_str(), 1)) {
      const std::string why = physfsError();
      releaseUserLocked();
      throw std::runtime_error(why);
    }
    mounts_[archive] = {mountPoint, 1};
    return mountPoint;
  }

  /// Mounts archive bytes that the caller keeps alive until release(key); returns the mount
  /// point and sets `key` (unique per call) or throws.
  std::string acquireMemory(const std::vector<std::byte>& bytes, const std::string& name, std::string& key) {
    std::lock_guard lock(mutex_);
    if (users_ == 0 && !PHYSFS_isInit()) initPhysfs();
    ++users_;
    const uint64_t id = nextId_++;
    const std::string mountPoint = "patharena_vfs/" + std::to_string(id);
    key = "patharena_memory_" + std::to_string(id) + "_" + name;  // physfs picks the archiver by extension first
    if (auto hazard = physfsZip64Hazard(bytes)) {
      releaseUserLocked();
      throw std::runtime_error(*hazard);
    }
    PHYSFS_Io* io = createByteIo(bytes.data(), bytes.size());
    if (!PHYSFS_mountIo(io, key.c_str(), mountPoint.c_str(), 1)) {
      const std::string why = physfsError();
      io->destroy(io);  // physfs leaves a refused Io to its owner
      releaseUserLocked();
      throw std::runtime_error(why);
    }
    mounts_[key] = {mountPoint, 1};
    return mountPoint;
  }

  void release(const std::string& archive) {
    std::lock_guard lock(mutex_);
    auto it = mounts_.find(archive);
    if (it != mounts_.end() && --it->second.refs == 0) {
      PHYSFS_unmount(archive.c_str());
      mounts_.erase(it);
    }
    releaseUserLocked();
  }

 private:
  struct Mount {
    std::string mountPoint;
    int refs = 0;
  };
  void releaseUserLocked() {
    if (--users_ == 0 && PHYSFS_isInit()) PHYSFS_deinit();
  }
  std::mutex mutex_;
  int users_ = 0;
  uint64_t nextId_ = 0;
  std::map<std::string, Mount> mounts_;
};

bool endsWithIgnoreCase(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && equalsIgnoreCase(s.substr(s.size() - suffix.size()), suffix);
}

}  // namespace

std::optional<std::string> normalizeGamePath(std::string_view path) {
  std::string out;
  out.reserve(path.size());
  for (char c : path) {
    if (c == '\0') return std::nullopt;
    if (c == '\\') c = '/';
    if (c == '/' && (out.empty() || out.back() == '/')) {
      if (out.empty()) return std::nullopt;  // absolute path
      continue;
    }
    out.push_back(c);
  }
  if (!out.empty() && out.back() == '/') out.pop_back();
  if (out.empty()) return std::nullopt;
  size_t start = 0;
  while (start <= out.size()) {
    const size_t end = std::min(out.find('/', start), out.size());
    if (out.compare(start, end - start, "..") == 0 && end - start == 2) return std::nullopt;
    start = end + 1;
  }
  return out;
}

GameFileSystem::GameFileSystem(const std::filesystem::path& gameDir) : root_(gameDir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(root_, ec))
    throw std::runtime_error("game folder '" + root_.string() + "' is not a readable directory");
  std::vector<std::filesystem::path> found;
  for (const auto& entry : std::filesystem::directory_iterator(root_, ec)) {
    if (entry.is_regular_file(ec) && endsWithIgnoreCase(entry.path().filename().string(), ".pk3"))
      found.push_back(entry.path());
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) {
    return comparePathsLikeEngine(a.filename().string(), b.filename().string()) < 0;
  });
  for (const auto& archive : found) {
    try {
      mountPoints_.push_back(PhysfsRegistry::instance().acquire(archive.string()));
      mountKeys_.push_back(archive.string());
      archives_.push_back(archive);
    } catch (const std::exception& e) {
      mountErrors_.push_back(archive.filename().string() + ": " + e.what());
    }
  }
  for (size_t i = 0; i < archives_.size(); ++i) indexArchive(i);  // later archives overwrite
}

GameFileSystem::GameFileSystem(std::vector<MemoryArchive> archives) {
  memoryBytes_.reserve(archives.size());
  for (auto& archive : archives) {
    memoryBytes_.push_back(std::move(archive.bytes));  // the buffer stays put when the vector grows
    try {
      std::string key;
      mountPoints_.push_back(PhysfsRegistry::instance().acquireMemory(memoryBytes_.back(), archive.name, key));
      mountKeys_.push_back(std::move(key));
      archives_.push_back(archive.name);
    } catch (const std::exception& e) {
      memoryBytes_.pop_back();
      mountErrors_.push_back(archive.name + ": " + e.what());
    }
  }
  for (size_t i = 0; i < archives_.size(); ++i) indexArchive(i);
}

GameFileSystem::~GameFileSystem() {
  for (const auto& key : mountKeys_) PhysfsRegistry::instance().release(key);
}

void GameFileSystem::indexArchive(size_t archive) {
  const std::string& mount = mountPoints_[archive];
  std::vector<std::string> pending{""};
  while (!pending.empty()) {
    const std::string dir = std::move(pending.back());
    pending.pop_back();
    const std::string physDir = dir.empty() ? mount : mount + "/" + dir;
    char** names = PHYSFS_enumerateFiles(physDir.c_str());
    if (!names) continue;
    for (char** n = names; *n; ++n) {
      // A hostile zip can make physfs list an empty name or "." for a folder: that folder again,
      // without end. Only plain names are followed, and folders at most kMaxFolderDepth deep.
      const std::string_view name(*n);
      if (name.empty() || name == "." || name == ".." || name.find('/') != std::string_view::npos) continue;
      const std::string inner = dir.empty() ? std::string(name) : dir + "/" + std::string(name);
      PHYSFS_Stat st;
      if (!PHYSFS_stat((mount + "/" + inner).c_str(), &st)) continue;
      if (st.filetype == PHYSFS_FILETYPE_DIRECTORY) {
        if (std::count(inner.begin(), inner.end(), '/') < kMaxFolderDepth) pending.push_back(inner);
      }
      else if (st.filetype == PHYSFS_FILETYPE_REGULAR) {
        // Keyed as lookups normalise ('\\' reads as '/'); a name no game path can reach is skipped.
        if (auto key = normalizeGamePath(inner)) index_[toLowerAscii(*key)] = {archive, inner};
      }
    }
    PHYSFS_freeList(names);
  }
}

std::optional<std::filesystem::path> GameFileSystem::loosePath(std::string_view path) const {
  if (root_.empty()) return std::nullopt;
  std::error_code ec;
  std::filesystem::path p = root_ / std::string(path);
  if (std::filesystem::is_regular_file(p, ec)) return p;
  return std::nullopt;
}

std::optional<std::vector<std::byte>> GameFileSystem::readFile(std::string_view rawPath) const {
  auto path = normalizeGamePath(rawPath);
  if (!path) return std::nullopt;
  if (auto loose = loosePath(*path)) {
    std::ifstream in(*loose, std::ios::binary);
    std::error_code ec;
    const auto size = std::filesystem::file_size(*loose, ec);
    if (!in || ec) throw FormatError(loose->string(), "file", "cannot be read");
    if (size > kMaxFileBytes) throw FormatError(loose->string(), "file", "larger than 256 MiB");
    std::vector<std::byte> bytes(size);
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
    if (static_cast<size_t>(in.gcount()) != size) throw FormatError(loose->string(), "file", "short read");
    return bytes;
  }
  auto it = index_.find(toLowerAscii(*path));
  if (it == index_.end()) return std::nullopt;
  const Entry& e = it->second;
  const std::string archiveName = archives_[e.archive].filename().string();
  const std::string physPath = mountPoints_[e.archive] + "/" + e.innerPath;
  PHYSFS_File* file = PHYSFS_openRead(physPath.c_str());
  if (!file) throw FormatError(archiveName, e.innerPath, "cannot open: " + physfsError());
  const PHYSFS_sint64 length = PHYSFS_fileLength(file);
  if (length < 0 || static_cast<uint64_t>(length) > kMaxFileBytes) {
    PHYSFS_close(file);
    throw FormatError(archiveName, e.innerPath, "bad or too large length");
  }
  std::vector<std::byte> bytes(static_cast<size_t>(length));
  const PHYSFS_sint64 got = PHYSFS_readBytes(file, bytes.data(), static_cast<PHYSFS_uint64>(length));
  PHYSFS_close(file);
  if (got != length) throw FormatError(archiveName, e.innerPath, "short read: " + physfsError());
  return bytes;
}

bool GameFileSystem::exists(std::string_view rawPath) const {
  auto path = normalizeGamePath(rawPath);
  if (!path) return false;
  return loosePath(*path).has_value() || index_.contains(toLowerAscii(*path));
}

std::string GameFileSystem::sourceOf(std::string_view rawPath) const {
  auto path = normalizeGamePath(rawPath);
  if (!path) return "";
  if (loosePath(*path)) return "(loose)";
  auto it = index_.find(toLowerAscii(*path));
  return it == index_.end() ? "" : archives_[it->second.archive].filename().string();
}

namespace {

/// The paths of a lower-cased-key map, in the engine's listing order.
std::vector<std::string> sortedLikeEngine(std::map<std::string, std::string> byKey) {
  std::vector<std::string> out;
  out.reserve(byKey.size());
  for (auto& [key, path] : byKey) out.push_back(std::move(path));
  std::sort(out.begin(), out.end(), [](const std::string& a, const std::string& b) {
    return comparePathsLikeEngine(a, b) < 0;
  });
  return out;
}

}  // namespace

std::vector<std::string> GameFileSystem::allFiles() const {
  std::map<std::string, std::string> byKey;
  for (const auto& [key, entry] : index_) byKey[key] = entry.innerPath;
  if (root_.empty()) return sortedLikeEngine(std::move(byKey));
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(root_, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    const std::string path = std::filesystem::relative(it->path(), root_, ec).generic_string();
    if (ec || path.empty()) continue;
    if (it.depth() == 0 && endsWithIgnoreCase(path, ".pk3")) continue;  // the archives themselves
    byKey[toLowerAscii(path)] = path;
  }
  return sortedLikeEngine(std::move(byKey));
}

std::vector<std::string> GameFileSystem::listFiles(std::string_view rawDir, std::string_view extension) const {
  std::string dir;
  if (!rawDir.empty() && rawDir != "/") {
    auto normalized = normalizeGamePath(rawDir);
    if (!normalized) return {};
    dir = *normalized;
  }
  const std::string prefix = dir.empty() ? "" : toLowerAscii(dir) + "/";
  std::map<std::string, std::string> byKey;  // lower-cased path -> path as listed
  for (const auto& [key, entry] : index_) {
    if (key.size() <= prefix.size() || key.compare(0, prefix.size(), prefix) != 0) continue;
    if (key.find('/', prefix.size()) != std::string::npos) continue;  // not a direct child
    if (!endsWithIgnoreCase(key, extension)) continue;
    byKey[key] = entry.innerPath;
  }
  std::error_code ec;
  const std::filesystem::path looseDir = dir.empty() ? root_ : root_ / dir;
  if (!root_.empty() && std::filesystem::is_directory(looseDir, ec)) {
    for (const auto& f : std::filesystem::directory_iterator(looseDir, ec)) {
      if (!f.is_regular_file(ec)) continue;
      const std::string name = f.path().filename().string();
      if (!endsWithIgnoreCase(name, extension)) continue;
      if (dir.empty() && endsWithIgnoreCase(name, ".pk3")) continue;  // the archives themselves
      const std::string path = dir.empty() ? name : dir + "/" + name;
      byKey[toLowerAscii(path)] = path;
    }
  }
  return sortedLikeEngine(std::move(byKey));
}

}  // namespace q3
