#pragma once
// Scalar traversal of the basic binary BVH: the reference every wide layout is checked against.
#include <cstdint>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/triangle_mesh.h"
#include "renderer/core/ray.h"

namespace pa::bvh_detail {

/// Closest hit (same contract as Blas::intersect; ray must be traceable).
bool intersectReference(const TriangleMesh& mesh, const BinaryBvh& bvh, Ray& ray, Hit& hit,
                        const HitFilter& filter, uint32_t instanceId);

/// Any hit (same contract as Blas::occluded; ray must be traceable).
bool occludedReference(const TriangleMesh& mesh, const BinaryBvh& bvh, const Ray& ray,
                       const HitFilter& filter, uint32_t instanceId);

}  // namespace pa::bvh_detail
