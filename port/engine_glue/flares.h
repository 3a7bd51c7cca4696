#pragma once
// Light flares as the stock renderer draws them with r_flares 1 (ioquake3 tr_flares.c, read for
// its rules): a flare surface of the map (origin, colour, facing normal) in view gets a
// screen-space quad of the flare shader, centred on its projected pixel, when the first surface
// seen at that pixel is not more than 24 units in front of it; its intensity fades in and out
// over real time (r_flareFade per second) as it becomes visible or hidden. Pure logic: the
// caller reads the depth and draws the quads.
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace glue {

/// A flare surface of the map (MST_FLARE: origin, colour, normal; zero normal = all directions).
struct Flare {
  glm::vec3 origin{};
  glm::vec3 color{1.0f};
  glm::vec3 normal{0.0f};
};

/// One view as the flare pass needs it: camera (Quake axes: forward, left, up), field of view in
/// degrees, its rectangle in window pixels (top-left origin) and the view's time in ms.
struct FlareView {
  glm::vec3 origin{}, forward{1, 0, 0}, left{0, 1, 0}, up{0, 0, 1};
  float fovX = 90.0f, fovY = 90.0f;
  int x = 0, y = 0, width = 0, height = 0;
  int timeMs = 0;
};

/// r_flareSize, r_flareFade and r_flareCoeff (stock defaults 40, 7, 150).
struct FlareParams {
  float size = 40.0f;
  float fade = 7.0f;
  float coeff = 150.0f;
};

/// A quad to draw with the flare shader: centre in window pixels (top-left origin), half its
/// edge in pixels, and its vertex colour (each channel in [0, 1]).
struct FlareQuad {
  float centerX = 0.0f, centerY = 0.0f, halfSize = 0.0f;
  glm::vec3 color{0.0f};
};

/// Distance along the camera ray through window pixel (x, y) (top-left origin) to the first
/// surface seen there; +infinity where only sky is seen.
using FlareDepthQuery = std::function<float(float x, float y)>;

/// The flares' fade state from view to view of the world (one chain of world views).
class FlareTracker {
 public:
  /// Resizes the state to `count` flares, all hidden (a new map).
  void reset(size_t count);
  /// One view: projects, tests against `depthAt` and fades every flare; appends the quads to
  /// draw, in flare order, to `out` (cleared first).
  void update(const FlareView& view, std::span<const Flare> flares, const FlareParams& params,
              const FlareDepthQuery& depthAt, std::vector<FlareQuad>& out);

 private:
  struct State {
    long long addedView = -2;   ///< view counter when the flare was last in view
    bool visible = false;
    int fadeTimeMs = 0;
  };
  std::vector<State> states_;
  long long viewCount_ = 0;
};

/// The stock flare size: half the quad's edge in pixels for a view `viewWidth` wide and a flare
/// `eyeDistance` units in front of the camera (at least 1).
float flareHalfSize(float viewWidth, float eyeDistance, float flareSize);
/// The stock distance falloff in [0, 1]: coeff size^2 / (distance + size sqrt(coeff))^2.
float flareIntensity(float halfSize, float eyeDistance, float coeff);

}  // namespace glue
