#include "port/q3formats/shader/shader_time.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace q3 {
namespace {

constexpr double kTwoPi = 6.28318530717958647692;

/// The table entry of `cycles`: trunc(cycles x 1024), wrapped into [0, 1024) as a mask does.
int tableIndex(double cycles) {
  const double scaled = cycles * kWaveTableSize;
  if (!std::isfinite(scaled)) return 0;
  const auto whole = static_cast<int64_t>(std::fmod(scaled, 1099511627776.0));   // 2^40: exact wrap
  return static_cast<int>(whole & (kWaveTableSize - 1));
}

float tableEntry(WaveFunc func, int i) {
  const double x = double(i) / kWaveTableSize;
  switch (func) {
    case WaveFunc::Sin: {   // stock fills entry i with sin(i x 360 / 1023 degrees): a period of 1023 entries
      const float degrees = static_cast<float>(i) * 360.0f / static_cast<float>(kWaveTableSize - 1);
      return static_cast<float>(std::sin(double(degrees) * kTwoPi / 360.0));
    }
    case WaveFunc::Square: return i < kWaveTableSize / 2 ? 1.0f : -1.0f;
    case WaveFunc::Triangle: {
      const double f = x < 0.5 ? x : x - 0.5;
      const double rise = f < 0.25 ? 4 * f : 2 - 4 * f;
      return static_cast<float>(x < 0.5 ? rise : -rise);
    }
    case WaveFunc::Sawtooth: return static_cast<float>(x);
    case WaveFunc::InverseSawtooth: return static_cast<float>(1 - x);
    case WaveFunc::Noise: return 0;
  }
  return 0;
}

/// A fixed pseudo-random value in [-1, 1] for a whole number.
float latticeValue(int64_t n) {
  uint64_t h = static_cast<uint64_t>(n) * 0x9E3779B97F4A7C15ull;
  h ^= h >> 31;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 29;
  return static_cast<float>(double(h >> 11) / double(1ull << 53) * 2.0 - 1.0);
}

}  // namespace

float waveTableValue(WaveFunc func, double cycles) {
  if (func == WaveFunc::Noise) return waveNoise(cycles);
  return tableEntry(func, tableIndex(cycles));
}

float waveNoise(double t) {
  if (!std::isfinite(t)) return 0;
  const double whole = std::floor(t);
  const double f = t - whole;
  const auto i = static_cast<int64_t>(whole);
  return static_cast<float>(latticeValue(i) + (latticeValue(i + 1) - latticeValue(i)) * f);
}

std::array<float, 2> UvWobble::offsetAt(float x, float y, float z) const {
  if (amplitude == 0) return {0, 0};
  const float ds = waveTableValue(WaveFunc::Sin, (double(x) + double(z)) / 1024.0 + phase) * amplitude;
  const float dt = waveTableValue(WaveFunc::Sin, double(y) / 1024.0 + phase) * amplitude;
  return {after.a * ds + after.b * dt, after.c * ds + after.d * dt};
}

TcModsAt tcModsAt(const std::vector<TcMod>& mods, double seconds, std::array<float, 2> entityScroll) {
  TcModsAt out;
  bool wobbling = false;
  for (const TcMod& m : mods) {
    UvAffine step;
    switch (m.kind) {
      case TcModKind::Scroll:
      case TcModKind::EntityTranslate: {
        const auto& speed = m.kind == TcModKind::Scroll ? m.scroll : entityScroll;
        const double s = speed[0] * seconds, t = speed[1] * seconds;
        step.tx = static_cast<float>(s - std::floor(s));   // stock keeps the fraction
        step.ty = static_cast<float>(t - std::floor(t));
        break;
      }
      case TcModKind::Scale:
        step.a = m.scroll[0];
        step.d = m.scroll[1];
        break;
      case TcModKind::Rotate: {   // about (0.5, 0.5); the angle is read from the sin table
        const double degrees = -double(m.degreesPerSecond) * seconds;
        const double scaled = degrees * (kWaveTableSize / 360.0);
        const auto index = std::isfinite(scaled) ? static_cast<int64_t>(std::fmod(scaled, 1099511627776.0)) : 0;
        const float sn = tableEntry(WaveFunc::Sin, static_cast<int>(index & (kWaveTableSize - 1)));
        const float cs = tableEntry(WaveFunc::Sin, static_cast<int>((index + kWaveTableSize / 4) & (kWaveTableSize - 1)));
        step = {cs, -sn, sn, cs, 0.5f - 0.5f * cs + 0.5f * sn, 0.5f - 0.5f * sn - 0.5f * cs};
        break;
      }
      case TcModKind::Stretch: {   // scale about the centre by 1 / wave
        const float w = m.wave.base + m.wave.amplitude * waveTableValue(m.wave.func, m.wave.phase + seconds * m.wave.frequency);
        const float p = w != 0 ? 1.0f / w : 1.0f;
        step = {p, 0, 0, p, 0.5f - 0.5f * p, 0.5f - 0.5f * p};
        break;
      }
      case TcModKind::Transform:   // s' = s m00 + t m10 + t0, t' = s m01 + t m11 + t1
        step = {m.matrix[0], m.matrix[2], m.matrix[1], m.matrix[3], m.translate[0], m.translate[1]};
        break;
      case TcModKind::Turb:
        if (!wobbling && std::isfinite(m.wave.amplitude) && std::isfinite(m.wave.phase + seconds * m.wave.frequency)) {
          wobbling = true;
          out.wobble.amplitude = m.wave.amplitude;
          out.wobble.phase = m.wave.phase + seconds * m.wave.frequency;
          out.wobble.after = UvAffine{};
        }
        continue;
    }
    // A step that is not finite (hostile numbers) is left out rather than poisoning the map.
    if (!std::isfinite(step.a) || !std::isfinite(step.b) || !std::isfinite(step.c) || !std::isfinite(step.d) ||
        !std::isfinite(step.tx) || !std::isfinite(step.ty))
      continue;
    out.affine = step.after(out.affine);
    if (wobbling) out.wobble.after = step.after(out.wobble.after);
  }
  return out;
}

bool tcModsAnimate(const std::vector<TcMod>& mods) {
  for (const TcMod& m : mods) {
    switch (m.kind) {
      case TcModKind::Scroll:
        if (m.scroll[0] != 0 || m.scroll[1] != 0) return true;
        break;
      case TcModKind::Rotate:
        if (m.degreesPerSecond != 0) return true;
        break;
      case TcModKind::Stretch:
        if (m.wave.amplitude != 0) return true;
        break;
      case TcModKind::Turb:
        if (m.wave.amplitude != 0) return true;
        break;
      case TcModKind::EntityTranslate: return true;
      case TcModKind::Scale:
      case TcModKind::Transform: break;
    }
  }
  return false;
}

size_t animMapFrame(size_t frames, float frequency, double seconds) {
  if (frames <= 1) return 0;
  const double scaled = seconds * frequency * kWaveTableSize;
  if (!std::isfinite(scaled) || scaled <= 0) return 0;
  const auto index = static_cast<int64_t>(std::min(scaled, 9.0e15)) >> 10;
  return static_cast<size_t>(index % static_cast<int64_t>(frames));
}

float rgbWaveAt(const WaveForm& wave, double seconds, float identityLight) {
  float glow;
  if (wave.func == WaveFunc::Noise)
    glow = wave.base + waveNoise((seconds + wave.phase) * wave.frequency) * wave.amplitude;
  else
    glow = (wave.base + waveTableValue(wave.func, wave.phase + seconds * wave.frequency) * wave.amplitude) * identityLight;
  return std::isfinite(glow) ? std::clamp(glow, 0.0f, 1.0f) : 0.0f;
}

float alphaWaveAt(const WaveForm& wave, double seconds) {
  const float alpha = wave.base + waveTableValue(wave.func, wave.phase + seconds * wave.frequency) * wave.amplitude;
  return std::isfinite(alpha) ? std::clamp(alpha, 0.0f, 1.0f) : 0.0f;
}

}  // namespace q3
