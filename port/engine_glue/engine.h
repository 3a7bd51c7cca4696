#pragma once
// A thin, typed wrapper around the engine's refimport_t: printing, files, cvars, commands.
// Never calls ri.Error (that longjmps): the module's C boundary does, after unwinding.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "port/engine_glue/ioq3_abi.h"

namespace glue {

/// Thrown inside the module for failures that must drop the engine to the menu (ERR_DROP).
class DropError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Thrown for failures the game cannot continue from (no window: ERR_FATAL).
class FatalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Services the engine provides, wrapped in C++ types. Copyable view over refimport_t.
class Engine {
 public:
  explicit Engine(const q3abi::refimport_t& ri) : ri_(ri) {}

  /// printf-style message to the console (level: q3abi::PRINT_*).
  void print(int level, const char* fmt, ...) const __attribute__((format(printf, 3, 4)));
  /// Prints a warning line prefixed with the module name.
  void warn(const std::string& message) const;
  /// Whole file from the game file system (pk3 or folder); nullopt when missing.
  std::optional<std::vector<uint8_t>> readFile(const std::string& path) const;
  /// True when the file exists in the writable home path.
  bool fileExists(const std::string& path) const;
  /// Writes a file under the game's home path.
  void writeFile(const std::string& path, const void* data, size_t size) const;
  /// Names (relative to dir) of files under dir ending with extension.
  std::vector<std::string> listFiles(const std::string& dir, const std::string& extension) const;
  /// Milliseconds since engine start.
  int milliseconds() const { return ri_.Milliseconds(); }
  /// Gets or creates a cvar.
  q3abi::cvar_t* cvar(const char* name, const char* defaultValue, int flags,
                      const char* description) const;
  /// Number of arguments of the command being executed.
  int argc() const { return ri_.Cmd_Argc(); }
  /// Argument i of the command being executed ("" when absent).
  std::string argv(int i) const;
  /// The raw import table (window hand-off, commands).
  const q3abi::refimport_t& ri() const { return ri_; }

 private:
  q3abi::refimport_t ri_;
};

/// Lower-case copy with '\\' turned into '/': Quake names are case-insensitive.
std::string normalizeName(std::string_view name);
/// name without its extension (".tga", ".jpg", ...), if any.
std::string stripExtension(std::string_view name);

}  // namespace glue
