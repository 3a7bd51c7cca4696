// Blas: validated mesh copy + reference binary BVH (+ the wide SIMD layout it is converted to).
// A rebuild reuses the previous build's memory (mesh copy, binary nodes, and, from the second
// build on, the builder's scratch arrays), so meshes rebuilt every frame do not page-fault
// fresh memory on each build.
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
  bvh_detail::BinaryBuildScratch scratch;   // kept between builds once the Blas is rebuilt
  uint32_t builds = 0;
};

Blas::Blas() : impl_(std::make_unique<Impl>()) {}
Blas::~Blas() = default;
Blas::Blas(Blas&&) noexcept = default;
Blas& Blas::operator=(Blas&&) noexcept = default;

void Blas::build(const BlasInput& input, const BvhBuildConfig& config) {
  // Invalid input or config throws here, before anything changes.
  bvh_detail::validateBuildConfig(config);
  bvh_detail::validateBlasInput(input);
  if (!impl_) impl_ = std::make_unique<Impl>();
  Impl& impl = *impl_;
  try {
    bvh_detail::assignTriangleMesh(input, impl.mesh);
    bvh_detail::buildBinaryBvh(impl.mesh, config, impl.scratch, impl.binary);
    bvh_detail::collapseToWide(impl.binary, impl.mesh, impl.wide);   // reuses the previous layout's memory
    if (!config.allowAvx512) impl.wide.kernel = bvh_detail::WideKernel::Baseline;
    // The root box is the union of all triangles.
    impl.bounds = impl.binary.empty() ? Bounds{} : impl.binary.nodes[0].bounds;
  } catch (...) {
    impl_ = std::make_unique<Impl>();   // out of memory or too large for the wide layout: left empty
    throw;
  }
  // A Blas built once (static geometry) does not hold on to the scratch arrays; one that is
  // rebuilt is likely to be rebuilt again (dynamic geometry) and keeps them.
  if (++impl.builds == 1) impl.scratch.release();
}

void Blas::refit(std::span<const glm::vec3> positions) {
  if (!impl_) impl_ = std::make_unique<Impl>();
  bvh_detail::updatePositions(impl_->mesh, positions);
  const std::vector<Bounds> triBounds = bvh_detail::triangleBounds(impl_->mesh);
  bvh_detail::refitBinaryBvh(impl_->binary, triBounds);
  const bvh_detail::WideKernel kernel = impl_->wide.kernel;   // as the build chose it
  impl_->wide = bvh_detail::collapseToWide(impl_->binary, impl_->mesh);
  if (impl_->builds > 0) impl_->wide.kernel = kernel;
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
