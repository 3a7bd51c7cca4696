#pragma once
// Dynamic resolution (r_pt_fps): the traced world view's resolution scale follows the measured
// frame time so that frames take about 1000 / fps milliseconds; TAAU (r_pt_taau) resolves every
// scale to the window, so the changes show as a little more or less detail, not as a jump.
#include <cstdint>

namespace glue {

/// Picks the resolution scale of the next frame from the last frames' wall times.
/// Frame cost is modelled as roughly proportional to the traced pixels (scale squared): after a
/// change it waits for kSettleFrames frames at the new scale, averages their times, and moves the
/// scale by sqrt(target / measured), damped, in steps of 1/32, only when the time is off the
/// target by more than the dead band.
class ResolutionController {
 public:
  /// Frames measured at one scale before the next change.
  static constexpr int kSettleFrames = 4;
  /// Relative distance from the target frame time that is left alone.
  static constexpr double kDeadBand = 0.08;

  /// Feeds the wall time of the frame just finished (ms) and returns the scale for the next one,
  /// in [minScale, 1]. targetFps <= 0 returns 1 and forgets the measurements.
  float update(double frameMs, float targetFps, float minScale);
  /// The scale update() returned last (1 before any).
  float scale() const { return scale_; }

 private:
  float scale_ = 1.0f;
  double sumMs_ = 0.0;
  int frames_ = 0;
};

}  // namespace glue
