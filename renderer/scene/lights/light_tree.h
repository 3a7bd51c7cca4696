#pragma once
// A bounding volume hierarchy over emitters for choosing one at a shading point (Conty Estevez
// and Kulla 2018, "Importance Sampling of Many Lights with Adaptive Tree Splitting", without the
// splitting): every node bounds its emitters' positions, total power and emission directions
// (a cone of normals plus the spread of emission around each normal). Descent from the root picks
// a child in proportion to an upper-bound estimate of what it can deliver to the point (power /
// distance^2, reduced by how far its normal cone and the point's hemisphere turn away), so the
// probability of an emitter is the product of the branch probabilities on its path. pmf() walks
// the same path back from the emitter's leaf, so sampling and MIS agree.
// The tree is built binary (bucketed orientation-aware splits) and collapsed to four children per
// node, whose bounds are stored four lanes wide with what the estimate needs precomputed
// (centre, half diagonal, cone sine): a descent weighs four children in SSE lanes per level, in
// half the levels of the binary tree.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/core/bounds.h"

namespace pa {

/// A cone of unit directions: those within angle acos(cosTheta) of axis. cosTheta = -1 is every
/// direction; an empty cone has cosTheta = +inf.
struct DirectionCone {
  glm::vec3 axis{0.0f, 0.0f, 1.0f};   ///< Unit axis.
  float cosTheta = 2.0f;              ///< Cosine of the half angle (> 1: empty).

  /// True when the cone holds no direction.
  bool empty() const { return cosTheta > 1.0f; }
  /// The cone of every direction.
  static DirectionCone entireSphere() { return {glm::vec3(0.0f, 0.0f, 1.0f), -1.0f}; }
};

/// The smallest cone (by half angle, about an axis in the plane of both axes) holding a and b.
DirectionCone coneUnion(const DirectionCone& a, const DirectionCone& b);

/// What the tree knows of one emitter or one group of them.
struct LightBounds {
  Bounds bounds;                  ///< Where the emitters lie.
  float power = 0.0f;             ///< Summed peak radiant intensity (importance = power x cos / d^2).
  DirectionCone normals;          ///< Bounds the emitters' normals (theta_o).
  float cosEmission = 0.0f;       ///< Cosine of the spread of emission around a normal (theta_e).
  bool twoSided = false;          ///< Emits on both sides of its normals.
  float range = 0.0f;             ///< Reaches no point farther than this from the bounds (0: no limit).
};

/// Bounds holding both a and b.
LightBounds boundsUnion(const LightBounds& a, const LightBounds& b);

/// Upper-bound estimate of the light `b` delivers to point p whose surface reflects only into the
/// hemisphere of unit normal n (n = 0: every direction). 0 when nothing of b can reach p.
float lightImportance(const LightBounds& b, const glm::vec3& p, const glm::vec3& n);

/// Immutable light tree; one leaf per emitter with positive power.
class LightTree {
 public:
  LightTree() = default;
  /// Builds the tree over the emitters (index = position in the span). Emitters with zero,
  /// negative or non-finite power or bounds are left out (their pmf is 0).
  explicit LightTree(std::span<const LightBounds> lights);
  /// The same, in place: a tree rebuilt over as many emitters as before allocates nothing.
  void rebuild(std::span<const LightBounds> lights);

  /// True when no emitter can be chosen.
  bool empty() const { return nodes_.empty(); }
  /// Picks an emitter for point p, normal n with u in [0, 1); false when none can reach p (then
  /// pmf() is 0 for every emitter; otherwise it sums to 1 over them).
  /// `rootReaches`: the caller has found importance(p, n) > 0, which is then not recomputed.
  bool sample(const glm::vec3& p, const glm::vec3& n, float u, uint32_t& index, float& pmf,
              bool rootReaches = false) const;
  /// Probability with which sample() picks emitter `index` at p, n (`rootReaches` as for sample()).
  float pmf(uint32_t index, const glm::vec3& p, const glm::vec3& n, bool rootReaches = false) const;
  /// The root's importance at p, n (0 for an empty tree): what the whole tree can deliver.
  float importance(const glm::vec3& p, const glm::vec3& n) const {
    return wide_.empty() ? 0.0f : lightImportance(root_, p, n);
  }
  /// Number of emitters in the tree (leaves).
  size_t emitterCount() const { return ids_.size(); }
  /// Number of four-wide nodes, for tests and statistics.
  size_t nodeCount() const { return wide_.size(); }

 private:
  /// A node of the binary build.
  struct Node {
    LightBounds bounds;
    uint32_t secondChild = 0;       ///< Interior: index of the second child (the first is this + 1).
    uint32_t light = UINT32_MAX;    ///< Leaf: emitter index; UINT32_MAX for interior nodes.
  };
  /// Up to four children, lane by lane, with what lightImportance() needs of each precomputed.
  /// Unused lanes have power 0.
  struct WideNode {
    alignas(16) float centreX[4], centreY[4], centreZ[4];
    alignas(16) float halfX[4], halfY[4], halfZ[4];
    alignas(16) float radius2[4], power[4];
    alignas(16) float axisX[4], axisY[4], axisZ[4];
    alignas(16) float cosO[4], sinO[4], cosEmission[4];
    alignas(16) float range[4];        ///< 0: no limit.
    alignas(16) float axisExtent[4];   ///< One-sided, one normal: box extent along it; else +inf.
    alignas(16) int32_t twoSided[4];   ///< -1 where the child emits on both sides.
    uint32_t child[4] = {0, 0, 0, 0};  ///< Wide node index, or kLeaf | emitter index.
    uint32_t parent = UINT32_MAX;      ///< (wide node << 2) | lane in it; UINT32_MAX at the root.
  };
  static constexpr uint32_t kLeaf = 0x80000000u;
  uint32_t build(std::span<const LightBounds> lights, std::span<uint32_t> ids, int depth);
  /// Collapses binary node `node` (interior) into a wide node whose parent link is `parent`.
  uint32_t collapse(uint32_t node, uint32_t parent);
  /// Branch probabilities of the four lanes of `node` at p, n (uniform over the used lanes when
  /// none reaches p).
  void childProbabilities(const WideNode& node, const glm::vec3& p, const glm::vec3& n, bool hasNormal,
                          float (&probability)[4]) const;

  LightBounds root_;                    ///< The whole tree's bounds.
  std::vector<WideNode> wide_;          ///< wide_[0] is the root (one lane when there is one emitter).
  std::vector<uint32_t> leafOfLight_;   ///< Emitter index -> (wide node << 2) | lane; UINT32_MAX when left out.
  // The binary build's working arrays, kept for rebuilds (ids_: the emitters in the tree).
  std::vector<Node> nodes_;
  std::vector<uint32_t> ids_;
};

}  // namespace pa
