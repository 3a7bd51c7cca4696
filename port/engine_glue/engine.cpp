#include "port/engine_glue/engine.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstring>

namespace glue {

void Engine::print(int level, const char* fmt, ...) const {
  char buffer[4096];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buffer, sizeof buffer, fmt, args);
  va_end(args);
  ri_.Printf(level, "%s", buffer);
}

void Engine::warn(const std::string& message) const {
  ri_.Printf(q3abi::PRINT_WARNING, "pathtracer: %s\n", message.c_str());
}

std::optional<std::vector<uint8_t>> Engine::readFile(const std::string& path) const {
  if (path.empty() || path.size() >= 256) return std::nullopt;
  void* buffer = nullptr;
  const long length = ri_.FS_ReadFile(path.c_str(), &buffer);
  if (length < 0 || buffer == nullptr) return std::nullopt;
  const auto* bytes = static_cast<const uint8_t*>(buffer);
  std::vector<uint8_t> data(bytes, bytes + length);
  ri_.FS_FreeFile(buffer);
  return data;
}

bool Engine::fileExists(const std::string& path) const {
  return ri_.FS_FileExists(path.c_str()) != 0;
}

void Engine::writeFile(const std::string& path, const void* data, size_t size) const {
  if (size > static_cast<size_t>(INT32_MAX)) throw std::runtime_error("file too large: " + path);
  ri_.FS_WriteFile(path.c_str(), data, static_cast<int>(size));
}

std::vector<std::string> Engine::listFiles(const std::string& dir,
                                           const std::string& extension) const {
  int count = 0;
  char** list = ri_.FS_ListFiles(dir.c_str(), extension.c_str(), &count);
  std::vector<std::string> names;
  if (list == nullptr) return names;
  for (int i = 0; i < count && list[i] != nullptr; ++i) names.emplace_back(list[i]);
  ri_.FS_FreeFileList(list);
  return names;
}

q3abi::cvar_t* Engine::cvar(const char* name, const char* defaultValue, int flags,
                            const char* description) const {
  q3abi::cvar_t* variable = ri_.Cvar_Get(name, defaultValue, flags);
  if (variable != nullptr && description != nullptr && ri_.Cvar_SetDescription != nullptr)
    ri_.Cvar_SetDescription(variable, description);
  return variable;
}

std::string Engine::argv(int i) const {
  const char* text = ri_.Cmd_Argv(i);
  return text != nullptr ? std::string(text) : std::string();
}

std::string normalizeName(std::string_view name) {
  std::string out(name);
  for (char& c : out) {
    if (c == '\\') c = '/';
    else if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

std::string stripExtension(std::string_view name) {
  const size_t dot = name.find_last_of('.');
  const size_t slash = name.find_last_of('/');
  if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash))
    return std::string(name);
  return std::string(name.substr(0, dot));
}

}  // namespace glue
