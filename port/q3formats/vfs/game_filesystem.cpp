#include "port/q3formats/vfs/game_filesystem.h"

#include <physfs.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <mutex>
#include <stdexcept>
#include <system_error>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/common/tokenizer.h"

namespace q3 {
namespace {

constexpr size_t kMaxFileBytes = size_t{1} << 28;  // 256 MiB: larger entries (zip bombs) are refused

std::string physfsError() {
  return PHYSFS_getErrorByCode(PHYSFS_getLastErrorCode());
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
    if (users_ == 0 && !PHYSFS_isInit() && !PHYSFS_init(nullptr))
      throw std::runtime_error("physfs init failed: " + physfsError());
    ++users_;
    auto it = mounts_.find(archive);
    if (it != mounts_.end()) {
      ++it->second.refs;
      return it->second.mountPoint;
    }
    const std::string mountPoint = "patharena_vfs/" + std::to_string(nextId_++);
    if (!PHYSFS_mount(archive.c_str(), mountPoint.c_str(), 1)) {
      const std::string why = physfsError();
      releaseUserLocked();
      throw std::runtime_error(why);
    }
    mounts_[archive] = {mountPoint, 1};
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
      archives_.push_back(archive);
    } catch (const std::exception& e) {
      mountErrors_.push_back(archive.filename().string() + ": " + e.what());
    }
  }
  for (size_t i = 0; i < archives_.size(); ++i) indexArchive(i);  // later archives overwrite
}

GameFileSystem::~GameFileSystem() {
  for (const auto& archive : archives_) PhysfsRegistry::instance().release(archive.string());
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
      const std::string inner = dir.empty() ? std::string(*n) : dir + "/" + *n;
      PHYSFS_Stat st;
      if (!PHYSFS_stat((mount + "/" + inner).c_str(), &st)) continue;
      if (st.filetype == PHYSFS_FILETYPE_DIRECTORY) pending.push_back(inner);
      else if (st.filetype == PHYSFS_FILETYPE_REGULAR) index_[toLowerAscii(inner)] = {archive, inner};
    }
    PHYSFS_freeList(names);
  }
}

std::optional<std::filesystem::path> GameFileSystem::loosePath(std::string_view path) const {
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
  if (std::filesystem::is_directory(looseDir, ec)) {
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
