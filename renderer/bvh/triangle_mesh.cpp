#include "renderer/bvh/triangle_mesh.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "renderer/bvh/watertight.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "renderer/core/finite.h"
#include "renderer/core/reuse.h"

namespace pa::bvh_detail {
namespace {

void validatePositions(std::span<const glm::vec3> positions) {
  for (size_t i = 0; i < positions.size(); ++i)
    if (!finite(positions[i]))
      throw std::invalid_argument("BlasInput.positions[" + std::to_string(i) + "] is not finite");
}

void computeDegenerate(TriangleMesh& mesh) {
  const uint32_t n = mesh.triangleCount();
  resizeReusing(mesh.degenerate, n);   // every flag is written below
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, 1 << 14), [&](const auto& r) {
    for (uint32_t t = r.begin(); t < r.end(); ++t)
      mesh.degenerate[t] = isDegenerateTriangle(mesh.vertex(t, 0), mesh.vertex(t, 1), mesh.vertex(t, 2));
  });
}

}  // namespace

void validateBlasInput(const BlasInput& input) {
  if (input.indices.size() % 3 != 0)
    throw std::invalid_argument("BlasInput.indices size " + std::to_string(input.indices.size()) +
                                " is not a multiple of 3");
  if (input.indices.size() / 3 >= (size_t(1) << 31))
    throw std::invalid_argument("BlasInput.indices: too many triangles");
  validatePositions(input.positions);
  for (size_t i = 0; i < input.indices.size(); ++i)
    if (input.indices[i] >= input.positions.size())
      throw std::invalid_argument("BlasInput.indices[" + std::to_string(i) + "] = " +
                                  std::to_string(input.indices[i]) + " is out of range (" +
                                  std::to_string(input.positions.size()) + " positions)");
  if (!input.rules.empty() && input.rules.size() != input.indices.size() / 3)
    throw std::invalid_argument("BlasInput.rules has " + std::to_string(input.rules.size()) +
                                " entries for " + std::to_string(input.indices.size() / 3) + " triangles");
  for (size_t i = 0; i < input.rules.size(); ++i)
    if (static_cast<uint8_t>(input.rules[i]) > static_cast<uint8_t>(HitRule::OneSided))
      throw std::invalid_argument("BlasInput.rules[" + std::to_string(i) + "] = " +
                                  std::to_string(static_cast<int>(input.rules[i])) + " is not a HitRule");
}

TriangleMesh makeTriangleMesh(const BlasInput& input) {
  validateBlasInput(input);
  TriangleMesh mesh;
  assignTriangleMesh(input, mesh);
  return mesh;
}

void assignTriangleMesh(const BlasInput& input, TriangleMesh& mesh) {
  assignReusing(mesh.positions, input.positions.begin(), input.positions.end());
  assignReusing(mesh.indices, input.indices.begin(), input.indices.end());
  assignReusing(mesh.rules, input.rules.begin(), input.rules.end());
  computeDegenerate(mesh);
}

void updatePositions(TriangleMesh& mesh, std::span<const glm::vec3> positions) {
  if (positions.size() != mesh.positions.size())
    throw std::invalid_argument("Blas::refit: " + std::to_string(positions.size()) +
                                " positions given, the mesh has " + std::to_string(mesh.positions.size()));
  validatePositions(positions);
  mesh.positions.assign(positions.begin(), positions.end());
  computeDegenerate(mesh);
}

std::vector<Bounds> triangleBounds(const TriangleMesh& mesh) {
  std::vector<Bounds> out;
  triangleBounds(mesh, out);
  return out;
}

void triangleBounds(const TriangleMesh& mesh, std::vector<Bounds>& out) {
  resizeReusing(out, mesh.triangleCount());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, out.size(), 1 << 14), [&](const auto& r) {
    for (size_t t = r.begin(); t < r.end(); ++t) {
      const auto tri = static_cast<uint32_t>(t);
      out[t].extend(mesh.vertex(tri, 0));
      out[t].extend(mesh.vertex(tri, 1));
      out[t].extend(mesh.vertex(tri, 2));
    }
  });
}

}  // namespace pa::bvh_detail
