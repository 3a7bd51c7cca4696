// Blas: validated mesh copy + reference binary BVH (+ the wide SIMD layout it is converted to).
#include <stdexcept>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/triangle_mesh.h"
#include "renderer/bvh/wide_bvh.h"

namespace pa {

struct Blas::Impl {
  bvh_detail::TriangleMesh mesh;
  bvh_detail::BinaryBvh binary;   // reference layout, kept for refit and validation
  bvh_detail::WideBvh wide;       // what rays traverse
  Bounds bounds;
};

Blas::Blas() : impl_(std::make_unique<Impl>()) {}
Blas::~Blas() = default;
Blas::Blas(Blas&&) noexcept = default;
Blas& Blas::operator=(Blas&&) noexcept = default;

void Blas::build(const BlasInput& input, const BvhBuildConfig& config) {
  bvh_detail::validateBuildConfig(config);
  auto next = std::make_unique<Impl>();
  next->mesh = bvh_detail::makeTriangleMesh(input);
  next->binary = bvh_detail::buildBinaryBvh(next->mesh, config);
  next->wide = bvh_detail::collapseToWide(next->binary, next->mesh);
  if (!next->binary.empty()) next->bounds = next->binary.nodes[0].bounds;   // the root box is the union of all triangles
  impl_ = std::move(next);
}

void Blas::refit(std::span<const glm::vec3> positions) {
  if (!impl_) impl_ = std::make_unique<Impl>();
  bvh_detail::updatePositions(impl_->mesh, positions);
  const std::vector<Bounds> triBounds = bvh_detail::triangleBounds(impl_->mesh);
  bvh_detail::refitBinaryBvh(impl_->binary, triBounds);
  impl_->wide = bvh_detail::collapseToWide(impl_->binary, impl_->mesh);
  impl_->bounds = Bounds{};
  for (const Bounds& b : triBounds) impl_->bounds.extend(b);
}

bool Blas::intersect(Ray& ray, Hit& hit, const HitFilter& filter, uint32_t instanceId) const {
  if (!impl_ || !bvh_detail::isTraceableRay(ray)) return false;
  return bvh_detail::intersectWide(impl_->wide, ray, hit, filter, instanceId);
}

bool Blas::occluded(const Ray& ray, const HitFilter& filter, uint32_t instanceId) const {
  if (!impl_ || !bvh_detail::isTraceableRay(ray)) return false;
  return bvh_detail::occludedWide(impl_->wide, ray, filter, instanceId);
}

Bounds Blas::bounds() const { return impl_ ? impl_->bounds : Bounds{}; }

uint32_t Blas::triangleCount() const { return impl_ ? impl_->mesh.triangleCount() : 0; }

}  // namespace pa
