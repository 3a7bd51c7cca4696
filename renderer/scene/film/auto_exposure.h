#pragma once
// Automatic exposure: one gain for a rendered image, metered on its linear radiance. The key
// of the picture (log-average luminance of the pixels that see the world, not the sky) is
// brought to a target key (Reinhard et al. 2002, "Photographic tone reproduction": 0.18 for a
// normal-key scene, 0.09 / 0.045 for low-key ones), within a clamped range of gains.
#include <cstddef>
#include <span>

#include <glm/vec3.hpp>

namespace pa {

/// What automatic exposure aims for and how far it may go.
struct AutoExposureSettings {
  /// Linear luminance the key is mapped to: Reinhard's low-key value. Game arenas are low-key
  /// (dark interiors lit by bright lamps); with the normal 0.18 the lit floors of oa_dm1 clip.
  float targetKey = 0.045f;
  float blackLevel = 1e-3f;   ///< Luminances below this enter the log-average as this value, so that
                              ///< black pixels (unlit or shadowed) weigh as "very dark", not minus infinity.
  float minGain = 0.125f;     ///< Smallest gain (1/8: three stops down).
  float maxGain = 16.0f;      ///< Largest gain (16: four stops up).
};

/// Which end of the gain range, if any, limited the gain.
enum class ExposureClamp : unsigned char { None, Min, Max };

/// The metered gain and what it was derived from.
struct AutoExposure {
  float gain = 1.0f;                          ///< Linear multiplier to apply before tonemapping.
  float key = 0.0f;                           ///< Log-average luminance of the metered pixels (0 = nothing metered).
  size_t meteredPixels = 0;                   ///< Pixels that entered the key.
  bool meteredSky = false;                    ///< True when every pixel saw the sky and the sky was metered.
  ExposureClamp clamped = ExposureClamp::None;  ///< Whether targetKey / key fell outside [minGain, maxGain].
};

/// Meters an image: the key is exp(mean(log(max(Y, blackLevel)))) over the pixels whose depth
/// is finite (they hit the world; Y = Rec. 709 luminance of the radiance); the gain is
/// targetKey / key clamped to [minGain, maxGain]. When no pixel hit the world, every pixel is
/// metered (a view of the sky only). Pixels with non-finite radiance are skipped; with nothing
/// left to meter the gain is 1. `depth` may be empty (every pixel is metered) or has one value
/// per radiance pixel; throws std::invalid_argument for other sizes or settings that are not
/// 0 < minGain <= maxGain, targetKey > 0, blackLevel > 0 (all finite).
AutoExposure meterAutoExposure(std::span<const glm::vec3> radiance, std::span<const float> depth,
                               const AutoExposureSettings& settings = {});

}  // namespace pa
