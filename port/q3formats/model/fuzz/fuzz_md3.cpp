// libFuzzer: MD3 bytes -> parser, vertex interpolation and tag interpolation.
#include <cstddef>
#include <cstdint>
#include <span>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/model/md3.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const q3::Md3Model m = q3::parseMd3(std::span(reinterpret_cast<const std::byte*>(data), size), "fuzz.md3");
    std::vector<q3::Md3Vec3> positions, normals;
    const int last = static_cast<int>(m.frames.size()) - 1;
    for (const auto& s : m.surfaces) q3::lerpSurface(s, m.frames.size(), last, 0, 0.3f, positions, normals);
    for (int t = 0; t < m.numTags; ++t) (void)q3::lerpTag(m, 0, last + 1, 0.5f, m.tag(0, static_cast<size_t>(t)).name);
  } catch (const q3::FormatError&) {
  }
  return 0;
}
