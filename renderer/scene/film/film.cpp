#include "renderer/scene/film/film.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

#include "renderer/core/prefetch.h"
#include "renderer/scene/integrator/display_composite.h"
#include "renderer/scene/sampling/warp.h"
#include "renderer/scene/textures/texture.h"

namespace pa {

namespace {

/// A sample's radiance and emission as the film counts them: black where not finite.
struct CountedLight {
  glm::vec3 radiance;
  glm::vec3 emission;
};

CountedLight countedLight(const PixelSample& s) {
  const bool ok = std::isfinite(s.radiance.x) && std::isfinite(s.radiance.y) && std::isfinite(s.radiance.z);
  const bool emissionOk = std::isfinite(s.emission.x) && std::isfinite(s.emission.y) && std::isfinite(s.emission.z);
  return {ok ? s.radiance : glm::vec3(0.0f), ok && emissionOk ? s.emission : glm::vec3(0.0f)};
}

}  // namespace

void PixelAccumulator::add(const PixelSample& s) {
  const auto [r, e] = countedLight(s);
  for (int c = 0; c < 3; ++c) {
    radiance[c] += r[c];
    emission[c] += e[c];
    albedo[c] += s.albedo[c];
    normal[c] += s.normal[c];
  }
  if (std::isfinite(s.depth)) {
    depthSum += s.depth;
    ++depthCount;
  }
  ++samples;
  luminance.add(sampling::luminance(r));
}

namespace {

/// tonemap(), inlined where the operator is a constant.
[[gnu::always_inline]] inline glm::vec3 tonemapped(const glm::vec3& x, Tonemap op) {
  switch (op) {
    case Tonemap::AcesFitted: {
      const glm::vec3 y = glm::max(x, glm::vec3(0.0f));
      return glm::clamp((y * (2.51f * y + 0.03f)) / (y * (2.43f * y + 0.59f) + 0.14f), 0.0f, 1.0f);
    }
    case Tonemap::Reinhard: {
      const float l = sampling::luminance(glm::max(x, glm::vec3(0.0f)));
      if (!(l > 0.0f)) return glm::vec3(0.0f);
      return glm::clamp(x * (1.0f / (1.0f + l)), 0.0f, 1.0f);
    }
    case Tonemap::Clamp:
      break;
  }
  return glm::clamp(x, 0.0f, 1.0f);
}

}  // namespace

glm::vec3 tonemap(const glm::vec3& x, Tonemap op) { return tonemapped(x, op); }

void Film::resize(uint32_t width, uint32_t height) {
  if (width == width_ && height == height_ && pixels_.size() == size_t{width} * height) return;
  width_ = width;
  height_ = height;
  const size_t n = size_t{width} * height;
  pixels_.assign(n, {});
  radiance_.assign(n, glm::vec3(0.0f));
  emission_.assign(n, glm::vec3(0.0f));
  albedo_.assign(n, glm::vec3(0.0f));
  normal_.assign(n, glm::vec3(0.0f));
  depth_.assign(n, 0.0f);
  variance_.assign(n, 0.0f);
  overlay_.assign(n, 0);
  rgba8_.assign(n * 4, 0);
  frames_ = 0;
  accumulatorsStale_ = false;
}

void Film::reset() {
  std::fill(pixels_.begin(), pixels_.end(), PixelAccumulator{});
  std::fill(overlay_.begin(), overlay_.end(), uint8_t{0});
  frames_ = 0;
  accumulatorsStale_ = false;
}

void Film::beginSingleSampleFrame(bool aovs, bool filtered) {
  frames_ = 0;
  // A frame without AOVs after one with them (or the reverse) keeps the accumulators stale.
  aovsWritten_ = aovs;
  filtered_ = filtered;
  accumulatorsStale_ = true;
}

void Film::writeSample(uint32_t x, uint32_t y, const PixelSample& s) {
  const size_t i = size_t{y} * width_ + x;
  const auto [r, e] = countedLight(s);
  // 0 + v as the sums, which start at +0, give: a -0 resolves to +0 there too.
  radiance_[i] = glm::vec3(0.0f) + r;
  if (aovsWritten_) {
    emission_[i] = glm::vec3(0.0f) + e;
    albedo_[i] = glm::vec3(0.0f) + s.albedo;
    normal_[i] = glm::vec3(0.0f) + s.normal;
  }
  depth_[i] = std::isfinite(s.depth) ? 0.0f + s.depth : std::numeric_limits<float>::infinity();
  variance_[i] = 0.0f;   // one sample
}

void Film::prefetchPixels(uint32_t x, uint32_t y, uint32_t n) const {
  const size_t i = size_t{y} * width_ + x;
  if (accumulatorsStale_) {
    prefetchForWrite(std::span(radiance_).subspan(i, n));
    if (aovsWritten_)
      for (const std::vector<glm::vec3>* v : {&emission_, &albedo_, &normal_}) prefetchForWrite(std::span(*v).subspan(i, n));
    prefetchForWrite(std::span(depth_).subspan(i, n));
    prefetchForWrite(std::span(variance_).subspan(i, n));
  } else {
    prefetchForWrite(std::span(pixels_).subspan(i, n));
  }
  prefetchForWrite(std::span(overlay_).subspan(i, n));
}

void Film::resumeAccumulation() {
  if (!accumulatorsStale_) return;
  if (!aovsWritten_) throw std::logic_error("Film::resumeAccumulation: the last frame left its AOVs out");
  if (filtered_) throw std::logic_error("Film::resumeAccumulation: the last frame's radiance was filtered");
  accumulatorsStale_ = false;
  // Each resolved value is its one sample as add() counted it: adding it again gives the same sums.
  for (size_t i = 0; i < pixels_.size(); ++i) {
    PixelSample s;
    s.radiance = radiance_[i];
    s.emission = emission_[i];
    s.albedo = albedo_[i];
    s.normal = normal_[i];
    s.depth = depth_[i];
    pixels_[i] = PixelAccumulator{};
    pixels_[i].add(s);
  }
}

void Film::resolveRows(uint32_t rowBegin, uint32_t rowEnd, float exposure, Tonemap op, LightingLook look) {
  resolveMeanRows(rowBegin, rowEnd);
  encodeRows(rowBegin, rowEnd, exposure, op, look);
}

glm::vec3 lightingLook(const glm::vec3& radiance, const glm::vec3& emission, const glm::vec3& albedo,
                       LightingLook look) {
  if (look == LightingLook::Physical) return radiance;
  constexpr float kMinAlbedo = 1.0f / 255.0f;
  glm::vec3 light(0.0f);   // the light the albedo reflected, per channel: a light-map texel
  float peak = 0.0f;
  for (int c = 0; c < 3; ++c) {
    if (!(albedo[c] >= kMinAlbedo)) continue;
    light[c] = std::max(0.0f, radiance[c] - emission[c]) / albedo[c];
    peak = std::max(peak, light[c]);
  }
  if (peak > 1.0f) light /= peak;   // an over-bright texel is scaled down as a whole
  // What the camera sees of emitters, glow stages and additive effects is added in display values,
  // as a stock framebuffer adds those stages, and the sum is clamped as its 8 bits are (added in
  // linear values it showed dimmer: an effect of display value 0.5 over a wall at 0.3 gave 0.58,
  // not 0.8).
  glm::vec3 out = radiance;
  for (int c = 0; c < 3; ++c) {
    if (!(albedo[c] >= kMinAlbedo)) continue;
    const float emitted = linearToSrgb(std::clamp(emission[c], 0.0f, 1.0f));
    out[c] = srgbToLinear(std::min(1.0f, linearToSrgb(albedo[c]) * light[c] + emitted));
  }
  return out;
}

void lightingLookRows(std::span<const glm::vec3> radiance, std::span<const glm::vec3> emission,
                      std::span<const glm::vec3> albedo, LightingLook look, std::span<glm::vec3> shown) {
  if (look == LightingLook::Physical) {
    std::copy(radiance.begin(), radiance.end(), shown.begin());
    return;
  }
  // lightingLook's steps with its 9 powf per pixel taken a chunk of channels at a time.
  constexpr float kMinAlbedo = 1.0f / 255.0f;
  constexpr size_t kChunk = 256;
  float curve[3 * kChunk], light[3 * kChunk], emitted[3 * kChunk];
  for (size_t at = 0; at < radiance.size(); at += kChunk) {
    const size_t m = std::min(kChunk, radiance.size() - at);
    for (size_t i = 0; i < m; ++i) {
      const size_t p = at + i;
      float peak = 0.0f;
      for (int c = 0; c < 3; ++c) {
        const size_t k = 3 * i + size_t(c);
        const bool lit = albedo[p][c] >= kMinAlbedo;
        light[k] = lit ? std::max(0.0f, radiance[p][c] - emission[p][c]) / albedo[p][c] : 0.0f;
        curve[k] = lit ? albedo[p][c] : 0.0f;
        emitted[k] = lit ? emission[p][c] : 0.0f;
        peak = std::max(peak, light[k]);
      }
      if (peak > 1.0f)
        for (int c = 0; c < 3; ++c) light[3 * i + size_t(c)] /= peak;
    }
    fastLinearToSrgb(std::span(curve, 3 * m));
    fastLinearToSrgb(std::span(emitted, 3 * m));   // clamped to [0, 1] first, as lightingLook does
    for (size_t k = 0; k < 3 * m; ++k) curve[k] = curve[k] * light[k] + emitted[k];
    fastSrgbToLinear(std::span(curve, 3 * m));      // the sum clamped to 1 first
    for (size_t i = 0; i < m; ++i) {
      const size_t p = at + i;
      for (int c = 0; c < 3; ++c)
        shown[p][c] = albedo[p][c] >= kMinAlbedo ? curve[3 * i + size_t(c)] : radiance[p][c];
    }
  }
}

void Film::resolveMeanRows(uint32_t rowBegin, uint32_t rowEnd) {
  for (size_t i = size_t{rowBegin} * width_; i < size_t{rowEnd} * width_; ++i) {
    const PixelAccumulator& p = pixels_[i];
    const double inv = p.samples > 0 ? 1.0 / static_cast<double>(p.samples) : 0.0;
    for (int c = 0; c < 3; ++c) {
      radiance_[i][c] = static_cast<float>(p.radiance[c] * inv);
      emission_[i][c] = static_cast<float>(p.emission[c] * inv);
      albedo_[i][c] = static_cast<float>(p.albedo[c] * inv);
      normal_[i][c] = static_cast<float>(p.normal[c] * inv);
    }
    depth_[i] = p.depthCount > 0 ? static_cast<float>(p.depthSum / static_cast<double>(p.depthCount))
                                 : std::numeric_limits<float>::infinity();
    variance_[i] = static_cast<float>(p.luminance.varianceOfMean());
  }
}

namespace {

/// The byte the exact curve gives a display value (what SrgbByteEncoder reproduces).
uint8_t exactSrgbByte(float x) {
  const float encoded = std::clamp(linearToSrgb(x), 0.0f, 1.0f);
  return encoded >= 0.0f ? static_cast<uint8_t>(std::lround(encoded * 255.0f)) : 0;
}

/// encodeWith's loop for one tonemap operator (its switch out of the loop).
template <Tonemap Op>
void encodeAs(const SrgbByteEncoder& encode, std::span<const glm::vec3> linear, float exposure, uint8_t* rgba8) {
  for (size_t i = 0; i < linear.size(); ++i) {
    const glm::vec3 display = tonemapped(linear[i] * exposure, Op);
    for (int c = 0; c < 3; ++c) rgba8[i * 4 + c] = encode(display[c]);
    rgba8[i * 4 + 3] = 255;
  }
}

void encodeWith(const SrgbByteEncoder& encode, std::span<const glm::vec3> linear, float exposure, Tonemap op,
                std::span<uint8_t> rgba8) {
  if (rgba8.size() != linear.size() * 4)
    throw std::invalid_argument("encodeDisplay: " + std::to_string(rgba8.size()) + " bytes for " +
                                std::to_string(linear.size()) + " pixels");
  switch (op) {
    case Tonemap::AcesFitted: encodeAs<Tonemap::AcesFitted>(encode, linear, exposure, rgba8.data()); return;
    case Tonemap::Reinhard: encodeAs<Tonemap::Reinhard>(encode, linear, exposure, rgba8.data()); return;
    case Tonemap::Clamp: break;
  }
  encodeAs<Tonemap::Clamp>(encode, linear, exposure, rgba8.data());
}

}  // namespace

SrgbByteEncoder::SrgbByteEncoder() {
  // Bisection over the non-negative floats' bit patterns (ordered as integers) in [0, 1].
  const uint32_t one = std::bit_cast<uint32_t>(1.0f);
  for (uint32_t k = 0; k < 255; ++k) {
    uint32_t lo = 0, hi = one;   // the first float with byte > k lies in (lo, hi]
    if (exactSrgbByte(0.0f) > k) {
      steps_[k] = 0.0f;
      continue;
    }
    while (hi - lo > 1) {
      const uint32_t mid = lo + (hi - lo) / 2;
      if (exactSrgbByte(std::bit_cast<float>(mid)) > k) hi = mid; else lo = mid;
    }
    steps_[k] = std::bit_cast<float>(hi);
  }
  steps_[255] = steps_[256] = std::numeric_limits<float>::infinity();
  for (uint32_t i = 0; i < kBuckets; ++i) {
    const float x = float(i) / float(kBuckets);
    uint32_t byte = 0;
    while (byte < 255 && steps_[byte] <= x) ++byte;
    bucketStart_[i] = static_cast<uint8_t>(byte);
  }
  // operator() climbs at most two bytes from a bucket's start: the bytes in bucket i lie between
  // bucketStart_[i] and the next bucket's (255 after the last).
  for (uint32_t i = 0; i < kBuckets; ++i) {
    const uint32_t next = i + 1 < kBuckets ? bucketStart_[i + 1] : 255;
    if (next > bucketStart_[i] + 2u) throw std::logic_error("SrgbByteEncoder: a bucket spans more than two bytes");
  }
}

void encodeDisplay(std::span<const glm::vec3> linear, float exposure, Tonemap op, std::span<uint8_t> rgba8) {
  encodeWith(SrgbByteEncoder(), linear, exposure, op, rgba8);
}

void Film::encodeRows(uint32_t rowBegin, uint32_t rowEnd, float exposure, Tonemap op, LightingLook look) {
  const size_t begin = size_t{rowBegin} * width_, count = size_t{rowEnd - rowBegin} * width_;
  if (look == LightingLook::Physical) {
    encodeWith(encoder_, std::span<const glm::vec3>(radiance_).subspan(begin, count), exposure, op,
               std::span<uint8_t>(rgba8_).subspan(begin * 4, count * 4));
    return;
  }
  // The shown values a chunk at a time, on the stack (no allocation per frame).
  constexpr size_t kChunk = 256;
  glm::vec3 shown[kChunk];
  for (size_t at = 0; at < count; at += kChunk) {
    const size_t m = std::min(kChunk, count - at);
    lightingLookRows(std::span<const glm::vec3>(radiance_).subspan(begin + at, m),
                     std::span<const glm::vec3>(emission_).subspan(begin + at, m),
                     std::span<const glm::vec3>(albedo_).subspan(begin + at, m), look, std::span(shown, m));
    encodeWith(encoder_, std::span<const glm::vec3>(shown, m), exposure, op,
               std::span<uint8_t>(rgba8_).subspan((begin + at) * 4, m * 4));
  }
}

}  // namespace pa
