#pragma once
// The Lightmap preset's compositing of see-through layers (additive and premultiplied-over
// surfaces crossed by camera rays) the way an 8-bit framebuffer does it: each layer is blended
// over what is behind it in display (sRGB-encoded) values, clamped to [0, 1] after each blend.
// Linear radiance composes light physically (the Direct and Path presets); display values are
// what a raster renderer's blend stages compose (0.5 + 0.5 adds to white, not to 0.73 encoded).
#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "renderer/scene/integrator/srgb_table.h"   // decodeColour
#include "renderer/scene/scene_types.h"
#include "renderer/scene/world/render_scene.h"

namespace pa {

/// pa::linearToSrgb of c clamped to [0, 1] without powf (largest difference 1.2e-7, tested).
float fastLinearToSrgb(float c);
/// pa::srgbToLinear of c clamped to [0, 1] without powf (largest difference 1.8e-7, tested).
float fastSrgbToLinear(float c);

/// fastLinearToSrgb of each value, in place (eight at a time).
void fastLinearToSrgb(std::span<float> values);
/// fastSrgbToLinear of each value, in place (eight at a time).
void fastSrgbToLinear(std::span<float> values);

/// fastLinearToSrgb of each channel of each colour's RGB, into `display` (resized to match;
/// the same values, eight channels at a time).
void encodeColors(std::span<const glm::vec4> linear, std::vector<glm::vec3>& display);
/// fastSrgbToLinear of each channel, in one pass (the same values).
glm::vec3 fastSrgbToLinear(const glm::vec3& c);
/// fastLinearToSrgb of each channel, in one pass (the same values).
glm::vec3 fastLinearToSrgb(const glm::vec3& c);

/// The product of two linear colours taken in display values, as linear radiance:
/// decode(encode(a) * encode(b)) (the stock texture x lightmap multiply of 8-bit values; the
/// linear product lin(a) lin(b) is up to 13x darker where the sRGB curve is linear, near black).
glm::vec3 displayProduct(const glm::vec3& a, const glm::vec3& b);
/// displayProduct of a linear colour and one already in display values: decode(encode(a) * b).
glm::vec3 displayProductWithDisplay(const glm::vec3& a, const glm::vec3& bDisplay);

/// fastLinearToSrgb of each channel of two colours, in one pass.
std::pair<glm::vec3, glm::vec3> encodeTwo(const glm::vec3& a, const glm::vec3& b);
/// pa::srgbToLinear of c clamped to [0, 1] by a table of 1025 steps, linearly interpolated
/// (largest difference 4.8e-7, tested): what decodeColour (srgb_table.h) computes.
float tableSrgbToLinear(float c);

/// A shine stage over a lit base, composed as framebuffer blending does (StockLook::shineBlend):
/// with dst = encode(base) and src = encode(shine.rgb), dst' = clamp(blend(dst, src)) (Add:
/// dst + src, Over: dst (1 - a) + src a with a = shine.a, Multiply: dst src, MultiplyInverse:
/// dst (1 - src), MultiplyAdd: dst (1 + src), Modulate2x: 2 dst src), then the base drawn
/// again over it with opacity baseRedrawn (0 = not redrawn): mix(dst', dst, baseRedrawn).
/// Linear in, linear out.
glm::vec3 composeShine(const glm::vec3& base, const glm::vec4& shine, LayerBlend blend, float baseRedrawn);

/// Layers in front of the surface a camera ray ends on, nearest first, composed at the end.
class DisplayComposite {
 public:
  /// Layers kept; farther ones beyond this are dropped (the nearest matter most).
  static constexpr uint32_t kCapacity = 32;

  /// No layers (the layer array is left unfilled: one composite is made per camera sample).
  DisplayComposite() {}

  /// One layer: linear colour it adds and the display-value multiplier of what is behind it
  /// (1 for additive layers, 1 - alpha for premultiplied ones; see pa::LayerBlend).
  struct Layer {
    glm::vec3 color{0.0f};
    glm::vec3 transmit{1.0f};
  };

  /// Appends the hits closer than `t` (in drawing order, as a query leaves them: nearest first)
  /// behind the layers already held (the layers of the ray's next segment lie behind this one's,
  /// e.g. through a portal). Their colours are display values where hits.displayValues, else
  /// linear (encoded here).
  void appendBefore(const AdditiveHits& hits, float t);
  /// Appends one layer (its linear colour encoded) behind the layers already held.
  void append(const Layer& layer);
  /// The layers, farthest first, blended over the linear colour `behind`:
  /// display = clamp(display * transmit + color's display value), returned as linear radiance.
  glm::vec3 over(const glm::vec3& behind) const;
  /// over() of what lies behind given as its display value in [0, 1] (not encoded again).
  glm::vec3 overDisplay(const glm::vec3& behind) const;
  /// Number of layers held.
  uint32_t size() const { return count_; }

 private:
  /// Layer without member initialisers: the array is not filled for every camera sample.
  struct Stored {
    glm::vec3 color;   ///< Display value added.
    glm::vec3 transmit;
  };
  std::array<Stored, kCapacity> layers_;   ///< First count_ are set.
  uint32_t count_ = 0;
};

}  // namespace pa
