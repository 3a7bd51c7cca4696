// Log-average metering of the world pixels (Reinhard et al. 2002, "key" of an image).
#include "renderer/scene/film/auto_exposure.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "renderer/core/finite.h"
#include "renderer/scene/sampling/warp.h"

namespace pa {
namespace {

bool positiveFinite(float x) { return std::isfinite(x) && x > 0.0f; }

void validate(const AutoExposureSettings& s) {
  if (!positiveFinite(s.targetKey)) throw std::invalid_argument("auto exposure: targetKey must be finite and > 0");
  if (!positiveFinite(s.blackLevel)) throw std::invalid_argument("auto exposure: blackLevel must be finite and > 0");
  if (!positiveFinite(s.minGain) || !positiveFinite(s.maxGain) || s.minGain > s.maxGain)
    throw std::invalid_argument("auto exposure: need 0 < minGain <= maxGain (finite)");
}


}  // namespace

AutoExposure meterAutoExposure(std::span<const glm::vec3> radiance, std::span<const float> depth,
                               const AutoExposureSettings& settings) {
  validate(settings);
  if (!depth.empty() && depth.size() != radiance.size())
    throw std::invalid_argument("auto exposure: " + std::to_string(depth.size()) + " depth values for " +
                                std::to_string(radiance.size()) + " pixels");
  const bool anyWorld =
      !depth.empty() && std::any_of(depth.begin(), depth.end(), [](float d) { return std::isfinite(d); });
  AutoExposure result;
  result.meteredSky = !depth.empty() && !anyWorld;
  double logSum = 0.0;
  for (size_t i = 0; i < radiance.size(); ++i) {
    if (anyWorld && !std::isfinite(depth[i])) continue;
    if (!finite(radiance[i])) continue;
    const float y = sampling::luminance(radiance[i]);
    logSum += std::log(static_cast<double>(std::max(y, settings.blackLevel)));
    ++result.meteredPixels;
  }
  if (result.meteredPixels == 0) return result;   // nothing to meter: gain 1
  result.key = static_cast<float>(std::exp(logSum / static_cast<double>(result.meteredPixels)));
  const float wanted = settings.targetKey / result.key;
  result.gain = std::clamp(wanted, settings.minGain, settings.maxGain);
  if (wanted > settings.maxGain) result.clamped = ExposureClamp::Max;
  else if (wanted < settings.minGain) result.clamped = ExposureClamp::Min;
  return result;
}

}  // namespace pa
