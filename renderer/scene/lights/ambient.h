#pragma once
// The scene's ambient terms (SkyDesc::ambientRadiance, SkyDesc::minimumRadiance): light a game
// level's author asked for on every surface, which no light source in the scene explains
// (Quake III worldspawn `_ambient`, added to every lightmap texel by the compiler, and
// `_minlight`, a floor on every texel). Both act at each diffuse or glossy path vertex on the
// radiance that vertex reflects from its light sample:
//   reflected' = max(reflected + a * ambient, a * minimum)   (per channel)
// with a the surface's diffuse albedo. `ambient` is exact: a uniform, unoccluded environment of
// that radiance seen by a Lambertian surface. `minimum` is a floor on an estimate, not on the
// mean: where one light sample is a fair estimate (smooth light) the image converges to the
// floor of the mean; where light samples are noisy (mostly 0, sometimes large) it converges to
// at most the floor added to the mean. Path applies both at every vertex, so the ambient light
// bounces as it did in the compiler's radiosity passes.
#include <algorithm>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace pa {

/// The ambient terms of a committed scene.
struct AmbientLight {
  glm::vec3 radiance{0.0f};   ///< Added: reflected += diffuse albedo x radiance.
  glm::vec3 minimum{0.0f};    ///< Floor: reflected >= diffuse albedo x minimum.

  /// True when either term can change a vertex's reflected radiance.
  bool active() const {
    return std::max({radiance.x, radiance.y, radiance.z, minimum.x, minimum.y, minimum.z}) > 0.0f;
  }
  /// The radiance a vertex of diffuse albedo `diffuseAlbedo` reflects once the ambient terms
  /// apply to `reflected` (what its light sample gave).
  glm::vec3 apply(const glm::vec3& reflected, const glm::vec3& diffuseAlbedo) const {
    return glm::max(reflected + diffuseAlbedo * radiance, diffuseAlbedo * minimum);
  }
};

}  // namespace pa
