// libFuzzer: .skin text -> parser and lookups.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "port/q3formats/model/skin.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const q3::Skin skin = q3::parseSkin(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.skin");
  for (const auto& s : skin.surfaces) (void)skin.shaderFor(s.surface);
  return 0;
}
