#pragma once
// A stand-in for ioquake3's client side of the renderer interface: a refimport_t backed by an
// in-memory file system (optionally over the installed OpenArena pk3s), recorded prints, cvars
// and commands. ri.Error longjmps like the engine does (to FakeEngine::errorJump).
#include <csetjmp>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "port/engine_glue/ioq3_abi.h"

namespace q3 {
class GameFileSystem;
}

namespace fake {

/// Frees a cvar and the strings the fake engine duplicated into it.
struct CvarDeleter {
  void operator()(q3abi::cvar_t* cvar) const;
};

/// The fake engine's state (one per test process; the C callbacks reach it statically).
struct FakeEngine {
  std::vector<std::string> prints;                       ///< Every Printf, in order.
  std::map<std::string, std::vector<uint8_t>> files;     ///< In-memory files (override pk3s).
  std::map<std::string, std::vector<uint8_t>> written;   ///< FS_WriteFile results.
  std::map<std::string, std::unique_ptr<q3abi::cvar_t, CvarDeleter>> cvars;
  std::map<std::string, void (*)()> commands;
  std::vector<std::string> args;                         ///< Cmd_Argv of the running command.
  std::unique_ptr<q3::GameFileSystem> game;              ///< Installed data, when present.
  int inInit = 0, inShutdown = 0;
  std::string lastError;
  int lastErrorLevel = -1;
  bool errorJumpArmed = false;
  std::jmp_buf errorJump;

  /// Printed text containing `needle`.
  bool printed(const std::string& needle) const;
  /// Sets a cvar's value (creating it).
  void setCvar(const std::string& name, const std::string& value);
  /// Runs a registered console command with arguments; false when it is not registered.
  bool runCommand(const std::vector<std::string>& argv);
};

/// The process-wide fake.
FakeEngine& engine();
/// Resets the fake (keeps the mounted game data).
void reset();
/// Mounts /usr/share/games/openarena/baseoa; false when it is not installed.
bool mountInstalledGame();
/// The import table handed to GetRefAPI.
q3abi::refimport_t imports();

}  // namespace fake
