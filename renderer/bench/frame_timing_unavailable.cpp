// Used while pa_scene (pa::Renderer) is not part of the build: frame times are reported as null.
#include "renderer/bench/frame_timing.h"

namespace pa::bench {

FrameTimes measureFrames(const BenchScene&, uint32_t) {
  FrameTimes out;
  out.note = "pa::Renderer (pa_scene) not available in this build";
  return out;
}

}  // namespace pa::bench
