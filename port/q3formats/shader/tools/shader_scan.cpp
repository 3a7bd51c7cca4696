// shader_scan GAME_DIR: parses every scripts/*.shader of a game folder and reports the
// keywords the parser does not know (target: none), files it had to ignore and totals.
#include <cstdio>
#include <map>
#include <string>

#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/vfs/game_filesystem.h"

int main(int argc, char** argv) {
  const std::string gameDir = argc > 1 ? argv[1] : "/usr/share/games/openarena/baseoa";
  try {
    q3::GameFileSystem fs(gameDir);
    q3::ShaderLibrary library;
    const auto scripts = q3::scriptsInPriorityOrder(fs.listFiles("scripts", ".shader"));
    size_t definitions = 0;
    for (const auto& name : scripts) {
      auto bytes = fs.readFile(name);
      if (!bytes) continue;
      std::string_view text(reinterpret_cast<const char*>(bytes->data()), bytes->size());
      const size_t before = library.size() + library.shadowedDefinitions();
      library.addScript(text, name);
      definitions += library.size() + library.shadowedDefinitions() - before;
    }
    std::map<std::string, int> unknown;
    size_t otherWarnings = 0;
    for (const auto& w : library.warnings()) {
      if (w.unknownKeyword) {
        unknown[w.keyword] += w.count;
        std::printf("unknown: %s:%d '%s' (x%d)\n", w.file.c_str(), w.line, w.keyword.c_str(), w.count);
      } else {
        ++otherWarnings;
        std::printf("warning: %s:%d shader '%s': %s: %s\n", w.file.c_str(), w.line, w.shader.c_str(),
                    w.keyword.c_str(), w.message.c_str());
      }
    }
    for (const auto& e : library.errors()) std::printf("ignored script: %s\n", e.c_str());
    std::printf("scripts %zu, definitions %zu, distinct shaders %zu, shadowed %zu\n", scripts.size(),
                definitions, library.size(), library.shadowedDefinitions());
    std::printf("unknown keywords %zu (distinct), other warnings %zu, ignored scripts %zu\n",
                unknown.size(), otherWarnings, library.errors().size());
    return unknown.empty() && library.errors().empty() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shader_scan: %s\n", e.what());
    return 2;
  }
}
