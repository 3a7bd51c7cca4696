#pragma once
// Shader time as the stock renderer evaluates it: its 1024-entry wave tables, tcMods composed in
// script order (turb included), the animMap frame and rgbGen / alphaGen wave values. Every
// function takes the shader time in seconds (refdef time, minus the entity's shaderTime).
#include <array>
#include <cstddef>
#include <vector>

#include "port/q3formats/shader/material.h"
#include "port/q3formats/shader/shader_types.h"

namespace q3 {

/// Entries per period of the stock wave tables.
inline constexpr int kWaveTableSize = 1024;

/// A periodic function at `cycles` as the stock renderer reads its tables: entry
/// trunc(cycles * 1024) mod 1024 of sin(2 pi i / 1023) (stock spreads one period over 1023
/// entries, so entry 256 is sin(90.09 degrees)), the square (+1 then -1), the triangle,
/// the sawtooth i / 1024 and the inverse sawtooth 1 - i / 1024. Noise is not a table: see waveNoise.
float waveTableValue(WaveFunc func, double cycles);

/// Noise of rgbGen / deform waves: linear between pseudo-random values in [-1, 1] at whole
/// values of `t`, the shape of the stock noise at x = y = z = 0 (stock draws its lattice values
/// from the C library's rand() when the renderer starts, after the engine seeded it for the run,
/// so its values differ from run to run and no fixed table can match them).
float waveNoise(double t);

/// The tcMod turb wobble: per vertex, uv += after.linear * amplitude * (sin(2 pi ((x + z) / 1024
/// + phase)), sin(2 pi (y / 1024 + phase))), x y z the vertex position (model space for models).
struct UvWobble {
  float amplitude = 0;   ///< 0 = no wobble
  double phase = 0;      ///< Cycles: the wave's phase + shader time x frequency.
  UvAffine after;        ///< The tcMods after the turb (only its linear part moves the offset).
  /// The offset at vertex position (x, y, z), read from the stock sin table.
  std::array<float, 2> offsetAt(float x, float y, float z) const;
};

/// A stage's tcMods at one shader time: uv' = affine(uv) + wobble.offsetAt(vertex).
struct TcModsAt {
  UvAffine affine;
  UvWobble wobble;
};

/// The tcMods at `seconds`, composed in script order as the stock renderer applies them.
/// entityTranslate scrolls by `entityScroll` units per second (refEntity shaderTexCoord). Only
/// the first turb wobbles; later ones are left out, as are steps whose numbers are not finite.
TcModsAt tcModsAt(const std::vector<TcMod>& mods, double seconds, std::array<float, 2> entityScroll = {0, 0});

/// True when the tcMods change with time (scroll, rotate, stretch, turb, entityTranslate).
bool tcModsAnimate(const std::vector<TcMod>& mods);

/// The animMap frame shown at `seconds` among `frames` frames at `frequency` frames per second,
/// counted in the stock way: trunc(seconds x frequency x 1024) / 1024, 0 when negative, mod frames.
size_t animMapFrame(size_t frames, float frequency, double seconds);

/// rgbGen wave's grey level in [0, 1]: base + noise((seconds + phase) x frequency) x amplitude for
/// noise, else the table wave x `identityLight` (1 / 2^overbright bits), clamped (0 when not finite).
float rgbWaveAt(const WaveForm& wave, double seconds, float identityLight = 1.0f);

/// alphaGen wave's alpha in [0, 1]: the table wave, clamped (0 when not finite).
float alphaWaveAt(const WaveForm& wave, double seconds);

}  // namespace q3
