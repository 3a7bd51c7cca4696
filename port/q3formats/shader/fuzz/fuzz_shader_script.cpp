// libFuzzer: shader script text -> parser, library, materials and uv animation.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/shader/material.h"
#include "port/q3formats/shader/shader_library.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  q3::ShaderLibrary library;
  library.addScript(text, "fuzz.shader");  // structural errors are caught inside
  for (const q3::ShaderDef& def : library.shaders()) {
    const q3::MaterialInfo m = q3::deriveMaterial(def);
    const q3::UvAffine uv = q3::uvTransformAt(m.uvAnimation, 12.5);
    (void)uv.apply(0.25f, 0.75f);
    for (const auto& stage : def.stages)
      if (stage.rgbGen == q3::RgbGen::Wave) (void)stage.rgbWave.evaluate(3.0);
    (void)library.find(def.name);
  }
  return 0;
}
