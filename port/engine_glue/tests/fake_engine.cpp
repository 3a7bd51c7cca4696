#include "fake_engine.h"

#include <chrono>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "port/q3formats/vfs/game_filesystem.h"

namespace fake {
namespace {

std::string lower(std::string s) {
  for (char& c : s) {
    if (c == '\\') c = '/';
    else if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return s;
}

char* duplicate(const std::string& s) {
  char* out = static_cast<char*>(std::malloc(s.size() + 1));
  std::memcpy(out, s.c_str(), s.size() + 1);
  return out;
}

void assignCvar(q3abi::cvar_t& cvar, const std::string& value) {
  std::free(cvar.string);
  cvar.string = duplicate(value);
  cvar.value = static_cast<float>(std::atof(value.c_str()));
  cvar.integer = std::atoi(value.c_str());
  cvar.modified = 1;
  ++cvar.modificationCount;
}

void Printf(int, const char* fmt, ...) {
  char buffer[8192];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buffer, sizeof buffer, fmt, args);
  va_end(args);
  engine().prints.emplace_back(buffer);
}

void Error(int level, const char* fmt, ...) {
  char buffer[8192];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buffer, sizeof buffer, fmt, args);
  va_end(args);
  FakeEngine& e = engine();
  e.lastError = buffer;
  e.lastErrorLevel = level;
  if (!e.errorJumpArmed) {
    std::fprintf(stderr, "ri.Error without a jump target: %s\n", buffer);
    std::abort();
  }
  e.errorJumpArmed = false;
  std::longjmp(e.errorJump, 1);
}

int Milliseconds() {
  static const auto start = std::chrono::steady_clock::now();
  return static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(
                              std::chrono::steady_clock::now() - start)
                              .count());
}

void* Alloc(int size, int) { return std::calloc(1, static_cast<size_t>(size)); }
void* AllocTemp(int size) { return std::malloc(static_cast<size_t>(size)); }
void* Malloc(int size) { return std::malloc(static_cast<size_t>(size)); }
void Free(void* p) { std::free(p); }

q3abi::cvar_t* CvarGet(const char* name, const char* value, int flags) {
  auto& slot = engine().cvars[name];
  if (!slot) {
    slot.reset(static_cast<q3abi::cvar_t*>(std::calloc(1, sizeof(q3abi::cvar_t))));
    slot->name = duplicate(name);
    assignCvar(*slot, value);
    slot->modified = 0;
  }
  slot->flags |= flags;
  return slot.get();
}

void CvarSet(const char* name, const char* value) { engine().setCvar(name, value); }
void CvarSetValue(const char* name, float value) { engine().setCvar(name, std::to_string(value)); }
void CvarCheckRange(q3abi::cvar_t* cvar, float lo, float hi, q3abi::qboolean integral) {
  cvar->validate = 1;
  cvar->min = lo;
  cvar->max = hi;
  cvar->integral = integral;
}
void CvarSetDescription(q3abi::cvar_t*, const char*) {}
int CvarIntegerValue(const char* name) {
  const auto found = engine().cvars.find(name);
  return found == engine().cvars.end() ? 0 : found->second->integer;
}

void CmdAdd(const char* name, void (*fn)()) { engine().commands[name] = fn; }
void CmdRemove(const char* name) { engine().commands.erase(name); }
int CmdArgc() { return static_cast<int>(engine().args.size()); }
char* CmdArgv(int i) {
  static std::string empty;
  auto& args = engine().args;
  return i >= 0 && static_cast<size_t>(i) < args.size() ? args[static_cast<size_t>(i)].data()
                                                        : empty.data();
}
void CmdExecute(int, const char*) {}
q3abi::byte* ClusterPVS(int) { return nullptr; }
void DrawDebug(void (*)(int, int, float*)) {}
int FileIsInPak(const char*, int*) { return 0; }

std::optional<std::vector<uint8_t>> find(const std::string& name) {
  FakeEngine& e = engine();
  if (const auto found = e.files.find(lower(name)); found != e.files.end()) return found->second;
  if (e.game) {
    if (auto bytes = e.game->readFile(name)) {
      const auto* p = reinterpret_cast<const uint8_t*>(bytes->data());
      return std::vector<uint8_t>(p, p + bytes->size());
    }
  }
  return std::nullopt;
}

long ReadFile(const char* name, void** buffer) {
  const auto bytes = find(name);
  if (!bytes) {
    if (buffer != nullptr) *buffer = nullptr;
    return -1;
  }
  if (buffer == nullptr) return static_cast<long>(bytes->size());
  auto* copy = static_cast<uint8_t*>(std::malloc(bytes->size() + 1));
  std::memcpy(copy, bytes->data(), bytes->size());
  copy[bytes->size()] = 0;   // the engine NUL-terminates too
  *buffer = copy;
  return static_cast<long>(bytes->size());
}
void FreeFile(void* buffer) { std::free(buffer); }

char** ListFiles(const char* dir, const char* ext, int* count) {
  std::vector<std::string> names;
  FakeEngine& e = engine();
  const std::string prefix = lower(dir) + "/";
  const std::string extension = lower(ext);
  for (const auto& [name, bytes] : e.files)
    if (name.rfind(prefix, 0) == 0 && name.size() >= extension.size() &&
        name.compare(name.size() - extension.size(), extension.size(), extension) == 0)
      names.push_back(name.substr(prefix.size()));
  if (e.game)
    for (const std::string& path : e.game->listFiles(dir, ext))
      names.push_back(path.substr(path.find_last_of('/') + 1));
  char** list = static_cast<char**>(std::calloc(names.size() + 1, sizeof(char*)));
  for (size_t i = 0; i < names.size(); ++i) list[i] = duplicate(names[i]);
  *count = static_cast<int>(names.size());
  return list;
}
void FreeFileList(char** list) {
  for (char** p = list; p != nullptr && *p != nullptr; ++p) std::free(*p);
  std::free(list);
}
void WriteFile(const char* path, const void* data, int size) {
  const auto* p = static_cast<const uint8_t*>(data);
  engine().written[path] = std::vector<uint8_t>(p, p + size);
}
q3abi::qboolean FileExists(const char* path) { return engine().written.count(path) ? 1 : 0; }
void CinUpload(int) {}
int CinPlay(const char*, int, int, int, int, int) { return -1; }
int CinRun(int) { return 0; }
void WriteAvi(const q3abi::byte*, int) {}
void InInit(void*) { ++engine().inInit; }
void InShutdown() { ++engine().inShutdown; }
void InRestart() {}
long Ftol(float f) { return static_cast<long>(f); }
void SetEnv(const char* name, const char* value) { setenv(name, value, 1); }
void Nothing() {}
q3abi::qboolean LowMemory() { return 0; }

}  // namespace

void CvarDeleter::operator()(q3abi::cvar_t* cvar) const {
  if (cvar == nullptr) return;
  std::free(cvar->name);
  std::free(cvar->string);
  std::free(cvar);
}

FakeEngine& engine() {
  static FakeEngine instance;
  return instance;
}

bool FakeEngine::printed(const std::string& needle) const {
  for (const std::string& line : prints)
    if (line.find(needle) != std::string::npos) return true;
  return false;
}

void FakeEngine::setCvar(const std::string& name, const std::string& value) {
  q3abi::cvar_t* cvar = CvarGet(name.c_str(), value.c_str(), 0);
  assignCvar(*cvar, value);
}

bool FakeEngine::runCommand(const std::vector<std::string>& argv) {
  const auto found = commands.find(argv.at(0));
  if (found == commands.end()) return false;
  args = argv;
  found->second();
  args.clear();
  return true;
}

void reset() {
  FakeEngine& e = engine();
  e.prints.clear();
  e.files.clear();
  e.written.clear();
  e.commands.clear();
  e.args.clear();
  e.inInit = e.inShutdown = 0;
  e.lastError.clear();
  e.lastErrorLevel = -1;
  e.errorJumpArmed = false;
}

bool mountInstalledGame() {
  const std::filesystem::path dir = "/usr/share/games/openarena/baseoa";
  FakeEngine& e = engine();
  if (e.game) return true;
  if (!std::filesystem::exists(dir / "pak0.pk3")) return false;
  e.game = std::make_unique<q3::GameFileSystem>(dir);
  return true;
}

q3abi::refimport_t imports() {
  q3abi::refimport_t ri{};
  ri.Printf = Printf;
  ri.Error = Error;
  ri.Milliseconds = Milliseconds;
  ri.Hunk_Alloc = Alloc;
  ri.Hunk_AllocateTempMemory = AllocTemp;
  ri.Hunk_FreeTempMemory = Free;
  ri.Malloc = Malloc;
  ri.Free = Free;
  ri.Cvar_Get = CvarGet;
  ri.Cvar_Set = CvarSet;
  ri.Cvar_SetValue = CvarSetValue;
  ri.Cvar_CheckRange = CvarCheckRange;
  ri.Cvar_SetDescription = CvarSetDescription;
  ri.Cvar_VariableIntegerValue = CvarIntegerValue;
  ri.Cmd_AddCommand = CmdAdd;
  ri.Cmd_RemoveCommand = CmdRemove;
  ri.Cmd_Argc = CmdArgc;
  ri.Cmd_Argv = CmdArgv;
  ri.Cmd_ExecuteText = CmdExecute;
  ri.CM_ClusterPVS = ClusterPVS;
  ri.CM_DrawDebugSurface = DrawDebug;
  ri.FS_FileIsInPAK = FileIsInPak;
  ri.FS_ReadFile = ReadFile;
  ri.FS_FreeFile = FreeFile;
  ri.FS_ListFiles = ListFiles;
  ri.FS_FreeFileList = FreeFileList;
  ri.FS_WriteFile = WriteFile;
  ri.FS_FileExists = FileExists;
  ri.CIN_UploadCinematic = CinUpload;
  ri.CIN_PlayCinematic = CinPlay;
  ri.CIN_RunCinematic = CinRun;
  ri.CL_WriteAVIVideoFrame = WriteAvi;
  ri.IN_Init = InInit;
  ri.IN_Shutdown = InShutdown;
  ri.IN_Restart = InRestart;
  ri.ftol = Ftol;
  ri.Sys_SetEnv = SetEnv;
  ri.Sys_GLimpSafeInit = Nothing;
  ri.Sys_GLimpInit = Nothing;
  ri.Sys_LowPhysicalMemory = LowMemory;
  return ri;
}

}  // namespace fake
