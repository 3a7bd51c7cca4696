#pragma once
// Light selection and sampling for next-event estimation: analytic lights (point, spot,
// directional), emissive triangles gathered at commit, and the sky. One alias table picks a
// category by estimated power: each directional light, the sky, and all local emitters (point
// and spot lights and emissive triangles together). Sun and sky power is the flux through the
// sky windows when the scene has them (an enclosed level lets in far less than its bounding
// disc). The local choice is made at the shading point, so weak nearby emitters are not starved
// by strong distant ones (game maps have ~100 lamps and hundreds to thousands of surface-light
// triangles): lamps against triangles in proportion to the lamps' summed weight there and the
// triangle tree's root importance; then a lamp in proportion to its unshadowed contribution
// (intensity x falloff x spot cone, exact), or a triangle by descending a light tree
// (light_tree.h) that weighs intensity, distance, emission cone and the point's hemisphere.
// The sky's and the sun's pdfs (MIS) do not depend on the shading point; a triangle's does
// (position and normal of the point that sampled it). Each light is then sampled by solid angle
// (point-like lights, sun cone, sky cosine lobe) or uniformly by area (triangles, converted to
// solid angle). Where an EnvironmentVisibility map says few rays from a point's surroundings reach
// sun or sky, the sun and sky keep only that fraction of their share there
// (environment_visibility.h); their pdfs then depend on the shading point too. Where a
// LampVisibility map says no ray from a point's surroundings reached a lamp, the lamp keeps
// LampVisibility::kHiddenWeight of its weight there (lamp_visibility.h).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "renderer/core/bounds.h"
#include "renderer/scene/lights/environment_visibility.h"
#include "renderer/scene/lights/lamp_visibility.h"
#include "renderer/scene/lights/light_tree.h"
#include "renderer/scene/lights/sky.h"
#include "renderer/scene/sampling/alias_table.h"
#include "renderer/scene/scene_types.h"
#include "renderer/scene/textures/texture.h"

namespace pa {

/// One emissive triangle in world space.
struct EmissiveTriangle {
  glm::vec3 p0{0.0f}, e1{0.0f}, e2{0.0f};   ///< Vertex 0 and edges to vertices 1 and 2.
  glm::vec3 normal{0.0f, 0.0f, 1.0f};      ///< Unit winding normal (front side).
  float area = 0.0f;
  glm::vec2 uv0{0.0f}, uv1{0.0f}, uv2{0.0f};   ///< Emission texture coordinates (transformed).
  glm::vec3 emission{0.0f};                ///< Radiance multiplier.
  const Texture* texture = nullptr;        ///< Emission map, or null.
  bool twoSided = true;                    ///< Emits from both faces.
  bool hittable = true;                    ///< Bounce rays can hit it (else NEE gets full weight).
};

/// Which light a sample lies on and where, independent of the shading point, so that another
/// point can evaluate the same sample (reservoir reuse, renderer/scene/restir). Each light's
/// points carry a probability measure of their own: the sphere or cone parameter of a lamp or sun,
/// barycentrics by area on a triangle, directions by solid angle / 4 pi for the sky.
struct LightPoint {
  /// The kind of light.
  enum class Kind : uint8_t { None, Lamp, Sun, Triangle, Sky };
  Kind kind = Kind::None;
  uint32_t index = 0;        ///< Analytic light (lamp, sun) or emissive triangle index.
  glm::vec3 where{0.0f};     ///< Lamp, sun: sample parameter (xy); triangle: barycentrics (xy); sky: unit direction.
};

/// A sampled light connection from a shading point.
struct LightSample {
  glm::vec3 wi{0.0f};         ///< Unit direction toward the light.
  float distance = 0.0f;      ///< To the light point (infinity for sun and sky).
  glm::vec3 radiance{0.0f};   ///< Arriving radiance (or irradiance for delta lights).
  float pdf = 0.0f;           ///< Solid-angle pdf including light selection (selection only for delta).
  bool delta = false;         ///< Cannot be hit by BSDF sampling: no MIS, weight 1.
  bool environment = false;   ///< Sun or sky: shadow rays pass sky surfaces.
  glm::vec3 lightPoint{0.0f};   ///< Sampled point on an area light (shadow ray end).
  glm::vec3 lightNormal{0.0f};  ///< Its geometric normal.
  LightPoint light;             ///< The sample as a point on its light (sample() and evaluate()).
  /// pdf x jacobian is the pdf over the light's own measure (LightPoint): |cos| area / d^2 for a
  /// triangle, 4 pi for the sky, 1 for lamps and suns (their pdf is already a selection).
  float jacobian = 1.0f;
};

/// Radiance emitted by an emissive triangle at barycentrics (b1, b2) toward a side.
glm::vec3 emittedRadiance(const EmissiveTriangle& tri, glm::vec2 bary, bool frontSide);

/// Immutable light sampling tables built at commit.
class LightSampler {
 public:
  LightSampler() = default;
  /// Builds the selection table. `lights` are live analytic lights. `skyWindows` holds
  /// area x unit normal of each sky-window triangle: when there are any, sun and sky power is
  /// what passes through them, else what falls on the scene's bounding disc.
  LightSampler(std::span<const LightDesc> lights, std::vector<EmissiveTriangle> triangles, const Sky& sky,
               const Bounds& sceneBounds, std::span<const glm::vec3> skyWindows = {});
  /// The same, in place (the environment visibility is dropped): rebuilding over as many lights
  /// as before allocates nothing.
  void rebuild(std::span<const LightDesc> lights, std::span<const EmissiveTriangle> triangles, const Sky& sky,
               const Bounds& sceneBounds, std::span<const glm::vec3> skyWindows = {});

  /// True when there is no light at all.
  bool empty() const { return table_.empty(); }
  /// Picks a light (u.x) and a point on it (u.y, u.z; u.w for the sky's cell choice) for
  /// shading point p with normal n (facing the viewer). With `skyRadiance` false a sky sample's
  /// radiance is left 0, for the caller to take skyRadiance() of its direction once its shadow
  /// ray passed (a SkyPicture may cost much per direction; most shadow rays toward the sky are
  /// blocked indoors).
  bool sample(const glm::vec3& p, const glm::vec3& n, const glm::vec4& u, LightSample& out,
              bool skyRadiance = true) const;
  /// The radiance a sky sample (LightPoint::Kind::Sky) toward wi brings: what sample() sets.
  glm::vec3 skyRadiance(const glm::vec3& wi) const { return sky_.lightingRadiance(wi); }
  /// The connection from shading point p with normal n to a point on a light that sample() could
  /// have produced there (wi, distance, radiance, lightPoint, lightNormal, environment, delta,
  /// jacobian; pdf is left unset). False when sample() at p, n gives that light probability 0
  /// (or the light no longer exists): reservoir reuse counts on the sampler's support.
  bool evaluate(const LightPoint& light, const glm::vec3& p, const glm::vec3& n, LightSample& out) const;
  /// Solid-angle pdf with which sample() picks the emissive triangle `index` at point q from
  /// point p with normal n (the arguments sample() was called with).
  float emissivePdf(uint32_t index, const glm::vec3& p, const glm::vec3& n, const glm::vec3& q) const;
  /// Probability with which sample() picks the emissive triangle `index` at p, n (no area pdf).
  float emissiveSelection(uint32_t index, const glm::vec3& p, const glm::vec3& n) const;
  /// Solid-angle pdf with which sample() picks sky direction wi from point p with normal n.
  float skyPdf(const glm::vec3& p, const glm::vec3& n, const glm::vec3& wi) const;
  /// True when sun or sky and local emitters share the choice: the only case where an
  /// EnvironmentVisibility map changes anything.
  bool mixesEnvironmentAndLocal() const { return localEntry_ != UINT32_MAX && environmentShare_ > 0.0; }
  /// The unit directions the suns that carry light travel (what an EnvironmentVisibility map
  /// traces); suns of zero intensity or colour are not among them.
  std::vector<glm::vec3> sunDirections() const;
  /// The same, written into `out` (its memory kept).
  void sunDirections(std::vector<glm::vec3>& out) const;
  /// Where sun and sky can reach (null: everywhere). Shared: it outlives commits that keep the
  /// world, the suns and the sky.
  void setEnvironmentVisibility(std::shared_ptr<const EnvironmentVisibility> visibility) {
    visibility_ = std::move(visibility);
  }
  /// Which lamps the surfaces of each region cannot see (null: none hidden). Applied to the lamps
  /// that stand at the same index as when it was traced (LampVisibility::sameLamp); the others
  /// keep their full weight. Shared: it outlives commits that keep the map's lamps.
  void setLampVisibility(std::shared_ptr<const LampVisibility> visibility);
  /// The point and spot lights that carry power, in the order a LampVisibility map is traced for.
  void localLamps(std::vector<LightDesc>& out) const;
  /// Picks a lamp (point or spot light) at p, n as sample() does with u in [0, 1): its index into
  /// the lights and the probability of that choice among the lamps. `reuseWeights` false
  /// recomputes every weight while choosing; the choice and probability are the same bit for bit.
  bool pickLamp(const glm::vec3& p, const glm::vec3& n, float u, bool reuseWeights, uint32_t& index,
                float& probability) const;
  /// The emissive triangles (index as in emissivePdf).
  std::span<const EmissiveTriangle> triangles() const { return triangles_; }

 private:
  bool sampleAnalytic(const LightDesc& light, const glm::vec3& p, const glm::vec2& u, LightSample& out) const;
  /// How the local entry divides at p between triangles and lamps.
  struct LocalSplit {
    float emissive = 0.0f;     ///< Probability of the triangles (1 - that of the lamps).
    double lampWeight = 0.0;   ///< Summed lamp weights at p (their normaliser).
  };
  /// The weights of the first kBufferedLamps lamps at a shading point and the running sum at the
  /// end of each group of eight, kept on the stack by sample() so that choosing a lamp does not
  /// recompute them.
  static constexpr uint32_t kBufferedLamps = 512;
  struct LampPrefix {
    float weight[kBufferedLamps];          ///< Weight of lamp k (localLights_ order) at the point.
    double groupEnd[kBufferedLamps / 8];   ///< weight[0] + ... + weight[8g + 7], summed as localSplit() sums.
    uint32_t count = 0;                    ///< Lamps stored (whole groups, at most kBufferedLamps).
  };
  /// How the local entry divides at p, n; stores the lamps' weights into `prefix` when not null.
  LocalSplit localSplit(const glm::vec3& p, const glm::vec3& n, LampPrefix* prefix = nullptr) const;
  /// Picks a lamp at p, n in proportion to its weight (u in [0,1), total = summed weights);
  /// returns its index into analytic_ and the probability of that choice among the lamps. Lamps
  /// in `prefix` (null: none) are chosen by binary search; the weights of the rest are recomputed.
  bool pickLocalLight(const glm::vec3& p, const glm::vec3& n, float u, double total, const LampPrefix* prefix,
                      uint32_t& index, float& probability) const;
  bool sampleTriangle(const EmissiveTriangle& tri, const glm::vec3& p, const glm::vec2& u, LightSample& out) const;
  /// The connection from p to the point of `tri` at barycentrics `bary`.
  bool connectTriangle(const EmissiveTriangle& tri, const glm::vec3& p, const glm::vec2& bary, LightSample& out) const;
  /// Probability that sample() picks table entry `entry` at p, n (the table's own where the
  /// environment keeps its full share).
  float entryProbability(uint32_t entry, const glm::vec3& p, const glm::vec3& n) const;
  /// Fraction of their table probability the sun and sky keep at p, n (before renormalising).
  float environmentScale(const glm::vec3& p, const glm::vec3& n) const {
    return visibility_ != nullptr && mixesEnvironmentAndLocal() ? visibility_->share(p, n) : 1.0f;
  }

  /// Builds everything from analytic_ and triangles_.
  void buildTables(const Sky& sky, const Bounds& sceneBounds, std::span<const glm::vec3> skyWindows);

  std::vector<LightDesc> analytic_;
  std::vector<EmissiveTriangle> triangles_;
  // buildTables' working arrays, kept for rebuilds.
  std::vector<double> power_, environmentPower_;
  std::vector<LightBounds> emitters_;
  Sky sky_;
  uint32_t skyEntry_ = UINT32_MAX;
  uint32_t localEntry_ = UINT32_MAX;   ///< The table entry of all local emitters.
  LightTree emissiveTree_;             ///< Over triangles_ (same indices).
  std::vector<uint32_t> localLights_;   ///< Indices into analytic_ of the point and spot lights that carry power.
  /// localLights_ eight to a group as structure of arrays (padding lanes carry no light): their
  /// weights at a shading point are computed eight per instruction.
  struct LampGroup {
    alignas(32) float x[8], y[8], z[8], radius[8], strength[8], range[8], inverseRange[8], linear[8];
    alignas(32) float spot[8], dx[8], dy[8], dz[8], cosOuter[8], cosInner[8];
    uint32_t live = 0;   ///< Bit per lane that holds a lamp.
    uint8_t mapped = 0;  ///< Bit per lane whose lamp the LampVisibility map was traced for.
    bool anyLinear = false, anyInverseSquare = false, anySpot = false;   ///< Which terms its lamps need.
    bool anyRange = false;   ///< Some lamp of the group has a reach (range > 0).
  };
  std::vector<LampGroup> lampGroups_;
  sampling::AliasTable table_;
  std::vector<uint32_t> environmentEntries_;   ///< Table entries of the suns and the sky.
  sampling::AliasTable environmentTable_;      ///< Over environmentEntries_, the same proportions.
  double environmentShare_ = 0.0;              ///< Summed table probability of those entries.
  std::shared_ptr<const EnvironmentVisibility> visibility_;
  std::shared_ptr<const LampVisibility> lampVisibility_;
  /// The lamp visibility map's bytes at one shading point: which lamps of each group it hides there.
  struct HiddenRow {
    const uint8_t* bits = nullptr;   ///< One byte per group (LampVisibility::rowBits); null: none hidden.
    uint32_t groups = 0;             ///< Groups the map covers (later lamps: dynamic lights, never hidden).
    /// Lanes of group g whose lamp is hidden, of those in `mapped`.
    uint8_t lanes(uint32_t g, uint8_t mapped) const { return g < groups ? uint8_t(bits[g] & mapped) : uint8_t(0); }
  };
  /// The lamp visibility map's row at p, n (nothing hidden where it has none).
  HiddenRow hiddenRow(const glm::vec3& p, const glm::vec3& n) const {
    const int64_t row = lampVisibility_ != nullptr ? lampVisibility_->row(p, n) : -1;
    if (row < 0) return {};
    return {lampVisibility_->rowBits(row), lampVisibility_->groupCount()};
  }
};

/// Distance falloff factor of a point or spot light at distance d (0 beyond range).
float distanceFalloff(const LightDesc& light, float d);
/// Upper bound of a point or spot light's unshadowed contribution (luminance-like scalar) at p,
/// over every point of its sphere; 0 only where no sample of the light can reach p.
float localLightWeight(const LightDesc& light, const glm::vec3& p);
/// The least cosine factor a lamp above the tangent plane keeps in its weight.
inline constexpr float kLeastLampCosine = 1.0f / 16.0f;
/// The cosine factor of a lamp's weight at p on a surface facing n (the sampler's lanes compute
/// the same up to rounding, with one division for falloff and cosine together): the cosine
/// toward the lamp's centre, raised by radius / distance for a sphere lamp (a bound over its
/// sphere), clamped to [kLeastLampCosine, 1]; 0 when the lamp lies wholly below the tangent
/// plane; 1 for n = 0 (no surface).
float lampCosineFactor(const LightDesc& light, const glm::vec3& p, const glm::vec3& n);
/// Angular factor of a spot light for a unit direction from the light toward the point.
float spotFactor(const LightDesc& light, const glm::vec3& fromLight);

}  // namespace pa
