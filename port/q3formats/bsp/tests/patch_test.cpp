// Patch tessellation: error bound, crack-freeness across shared edges, orientation.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <tuple>

#include <glm/geometric.hpp>

#include "port/q3formats/bsp/patch.h"
#include "port/q3formats/bsp/tessellate.h"
#include "port/q3formats/bsp/tests/bsp_writer.h"

namespace q3 {
namespace {

using Controls = std::vector<glm::vec3>;

struct PatchSpec {
  int width, height;
  Controls controls;
  glm::vec3 normal{0, 0, 1};
};

BspFile mapWithPatches(const std::vector<PatchSpec>& patches) {
  testing::BspWriter w;
  for (const auto& p : patches) w.addPatch(p.width, p.height, p.controls, p.normal);
  w.finishWorld({-1024, -1024, -1024}, {1024, 1024, 1024});
  return parseBsp(w.build(), "patches.bsp");
}

PatchControlGrid gridOf(const BspFile& bsp, size_t surface) {
  const auto& s = bsp.surfaces[surface];
  return {s.patchWidth, s.patchHeight, std::span<const BspDrawVert>(bsp.drawVerts).subspan(s.firstVert, s.numVerts)};
}

/// Largest distance between triangle points and the surface at the same parameters (the test
/// maps' st coordinates are the patch parameters scaled to [0, 1]).
float measuredError(const PatchControlGrid& grid, const SurfaceMesh& mesh) {
  float worst = 0;
  constexpr int kSteps = 8;
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    const MeshVertex* v[3] = {&mesh.vertices[mesh.indices[t]], &mesh.vertices[mesh.indices[t + 1]],
                              &mesh.vertices[mesh.indices[t + 2]]};
    for (int i = 0; i <= kSteps; ++i)
      for (int j = 0; i + j <= kSteps; ++j) {
        const float a = float(i) / kSteps, b = float(j) / kSteps, c = 1 - a - b;
        const glm::vec3 p = a * v[0]->position + b * v[1]->position + c * v[2]->position;
        const glm::vec2 uv = a * v[0]->uv + b * v[1]->uv + c * v[2]->uv;
        const glm::vec3 exact = evaluatePatchPosition(grid, uv.x * grid.spansU(), uv.y * grid.spansV());
        worst = std::max(worst, glm::length(p - exact));
      }
  }
  return worst;
}

PatchSpec wave() {  // 5x3, curved along u
  return {5, 3, {{0, 0, 0}, {64, 0, 64}, {128, 0, 0}, {192, 0, -64}, {256, 0, 0},
                 {0, 64, 0}, {64, 64, 64}, {128, 64, 0}, {192, 64, -64}, {256, 64, 0},
                 {0, 128, 0}, {64, 128, 64}, {128, 128, 0}, {192, 128, -64}, {256, 128, 0}}};
}
PatchSpec quarterPipe() {  // 3x3 quarter cylinder of radius 256 along y
  return {3, 3, {{256, 0, 0}, {256, 0, 256}, {0, 0, 256},
                 {256, 128, 0}, {256, 128, 256}, {0, 128, 256},
                 {256, 256, 0}, {256, 256, 256}, {0, 256, 256}}};
}
PatchSpec bumpy(unsigned seed) {  // 7x5 random heights: curved both ways and twisted
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> height(-96, 96);
  PatchSpec p{7, 5, {}};
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x) p.controls.push_back({x * 48.0f, y * 48.0f, height(rng)});
  return p;
}

TEST(Patch, FlatPatchNeedsOneSegmentPerSpan) {
  PatchSpec flat{5, 3, {}};
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) flat.controls.push_back({x * 32.0f, y * 32.0f, 0});
  const BspFile bsp = mapWithPatches({flat});
  const auto sub = requiredSubdivision(gridOf(bsp, 0), 0.01f, 64);
  EXPECT_EQ(sub.uSegments, (std::vector<int>{1, 1}));
  EXPECT_EQ(sub.vSegments, (std::vector<int>{1}));
  const auto meshes = tessellateSurfaces(bsp);
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0].vertices.size(), 3u * 2u);
  EXPECT_EQ(meshes[0].indices.size(), 4u * 3u);
  for (const auto& v : meshes[0].vertices) EXPECT_NEAR(glm::distance(v.normal, glm::vec3(0, 0, 1)), 0, 1e-6);
}

TEST(Patch, QuadraticCurveChordErrorMatchesTheBoundExactly) {
  // A single parabola: chord error with N segments is |p0 - 2p1 + p2| / (4 N^2).
  const BspFile bsp = mapWithPatches({quarterPipe()});
  const auto grid = gridOf(bsp, 0);
  // second difference (256,0,0)-(512,0,512)+(0,0,256) has length 256*sqrt(2)
  const float expected = 256.0f * std::sqrt(2.0f) / 4.0f / 16.0f;  // N = 4
  EXPECT_NEAR(patchPieceErrorBound(grid, 0, 0, 4, 1), expected, 1e-3);
}

TEST(Patch, TessellationStaysWithinTheErrorBound) {
  const std::vector<PatchSpec> patches = {wave(), quarterPipe(), bumpy(1), bumpy(2)};
  const BspFile bsp = mapWithPatches(patches);
  for (float tolerance : {16.0f, 4.0f, 1.0f, 0.25f}) {
    TessellationOptions options;
    options.maxError = tolerance;
    options.stitchPatches = false;
    const auto meshes = tessellateSurfaces(bsp, options);
    ASSERT_EQ(meshes.size(), patches.size());
    for (size_t k = 0; k < meshes.size(); ++k) {
      SCOPED_TRACE("patch " + std::to_string(k) + " tolerance " + std::to_string(tolerance));
      const float error = measuredError(gridOf(bsp, k), meshes[k]);
      EXPECT_LE(error, tolerance * 1.001f + 1e-3f);
    }
  }
}

TEST(Patch, FinerToleranceGivesMoreTrianglesAndTheBoundIsNotWasteful) {
  const BspFile bsp = mapWithPatches({quarterPipe()});
  size_t previous = 0;
  for (float tolerance : {64.0f, 16.0f, 4.0f, 1.0f}) {
    TessellationOptions options;
    options.maxError = tolerance;
    const auto meshes = tessellateSurfaces(bsp, options);
    EXPECT_GT(meshes[0].indices.size(), previous);
    previous = meshes[0].indices.size();
    // Powers of two: the achieved error is at least a quarter of the tolerance on a pure curve.
    EXPECT_GT(measuredError(gridOf(bsp, 0), meshes[0]), tolerance / 4.5f);
  }
}

/// Positions of every vertex of `mesh` lying in the plane x == 0.
std::set<std::tuple<float, float, float>> verticesOnPlaneX0(const SurfaceMesh& mesh) {
  std::set<std::tuple<float, float, float>> out;
  for (const auto& v : mesh.vertices)
    if (v.position.x == 0) out.insert({v.position.x, v.position.y, v.position.z});
  return out;
}

/// Two 3x3 patches sharing their edge in the plane x = 0: `left` is nearly flat, `right` bulges
/// strongly, so on their own they cut the shared curve differently.
std::vector<PatchSpec> sharedEdgePair(bool reverseRight, bool transposeRight) {
  const Controls edge = {{0, 0, 0}, {0, 128, 160}, {0, 256, 0}};
  PatchSpec left{3, 3, {}};
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) left.controls.push_back(x == 2 ? edge[y] : edge[y] + glm::vec3((x - 2) * 64.0f, 0, 0));
  // right: column 0 is the edge; its far columns swing much harder along y.
  glm::vec3 right[3][3];  // [row][col]
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x)
      right[y][x] = x == 0 ? edge[y] : edge[y] + glm::vec3(x * 64.0f, 0, 0) + glm::vec3(0, 0, y == 1 ? x * 600.0f : 0);
  PatchSpec r{3, 3, {}};
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) {
      const int row = reverseRight ? 2 - y : y;
      r.controls.push_back(transposeRight ? right[x][row] : right[row][x]);
    }
  return {left, r};
}

TEST(Patch, SharedEdgesGetIdenticalVerticesInAnyOrientation) {
  for (bool reverse : {false, true})
    for (bool transpose : {false, true}) {
      SCOPED_TRACE(std::string(reverse ? "reversed" : "same direction") + (transpose ? ", transposed" : ""));
      const BspFile bsp = mapWithPatches(sharedEdgePair(reverse, transpose));
      TessellationOptions unstitched;
      unstitched.stitchPatches = false;
      const auto loose = tessellateSurfaces(bsp, unstitched);
      ASSERT_EQ(loose.size(), 2u);
      EXPECT_NE(verticesOnPlaneX0(loose[0]), verticesOnPlaneX0(loose[1])) << "test needs different cuts";
      EXPECT_GT(measurePatchSeams(loose).cracks, 0u);

      const auto meshes = tessellateSurfaces(bsp);
      const auto a = verticesOnPlaneX0(meshes[0]), b = verticesOnPlaneX0(meshes[1]);
      EXPECT_EQ(a, b);
      EXPECT_GE(a.size(), 5u);
      const auto seams = measurePatchSeams(meshes);
      EXPECT_EQ(seams.tJunctions, 0u);
      EXPECT_EQ(seams.cracks, 0u);
      EXPECT_LE(measuredError(gridOf(bsp, 0), meshes[0]), 4.0f * 1.001f);
    }
}

TEST(Patch, ControlPointsWithFloatNoiseAreWeldedBeforeStitching) {
  // Shipped maps store one patch's corner as 15.9999943 and its neighbour's as 16.
  auto pair = sharedEdgePair(false, false);
  for (int y = 0; y < 3; ++y) pair[0].controls[y * 3 + 2].z += 6e-6f * (y + 1);
  const BspFile bsp = mapWithPatches(pair);
  TessellationOptions noWeld;
  noWeld.weldDistance = 0;
  noWeld.seamTolerance = 0;  // the mesh-level seam closing would hide it
  EXPECT_GT(measurePatchSeams(tessellateSurfaces(bsp, noWeld)).cracks, 0u);
  const auto meshes = tessellateSurfaces(bsp);
  EXPECT_EQ(verticesOnPlaneX0(meshes[0]), verticesOnPlaneX0(meshes[1]));
  const auto seams = measurePatchSeams(meshes);
  EXPECT_EQ(seams.tJunctions + seams.cracks, 0u);
}

TEST(Patch, StitchingPropagatesAlongAChainOfPatches) {
  // A - B - C side by side; only C is strongly curved along y, and A must follow it through B.
  auto row = [](float x0, float bulge) {
    PatchSpec p{3, 3, {}};
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 3; ++x)
        p.controls.push_back({x0 + x * 64.0f, y * 128.0f, y == 1 ? (x == 0 ? 100.0f : bulge * x + 100.0f) : 0});
    return p;
  };
  PatchSpec a = row(-128, 0), b = row(0, 0), c = row(128, 900);
  // Make the shared edges exactly equal: B's right column = C's left column etc.
  for (int y = 0; y < 3; ++y) {
    a.controls[y * 3 + 2] = b.controls[y * 3 + 0];
    b.controls[y * 3 + 2] = c.controls[y * 3 + 0];
  }
  const BspFile bsp = mapWithPatches({a, b, c});
  const auto meshes = tessellateSurfaces(bsp);
  std::vector<PatchSubdivision> subs;
  std::vector<PatchControlGrid> grids;
  for (size_t k = 0; k < 3; ++k) {
    grids.push_back(gridOf(bsp, k));
    subs.push_back(requiredSubdivision(grids.back(), 4.0f, 64));
  }
  EXPECT_LT(subs[0].vSegments[0], subs[2].vSegments[0]);
  matchSharedPatchEdges(grids, subs);
  EXPECT_EQ(subs[0].vSegments[0], subs[2].vSegments[0]);
  const auto seams = measurePatchSeams(meshes);
  EXPECT_EQ(seams.tJunctions + seams.cracks, 0u);
}

TEST(Patch, CollapsedRowsMakeNoDegenerateTrianglesAndFiniteNormals) {
  PatchSpec cone{3, 3, {{0, 0, 128}, {0, 0, 128}, {0, 0, 128},  // apex row collapsed
                        {64, 0, 64}, {64, 64, 64}, {0, 64, 64},
                        {128, 0, 0}, {128, 128, 0}, {0, 128, 0}}};
  const BspFile bsp = mapWithPatches({cone});
  const auto meshes = tessellateSurfaces(bsp);
  ASSERT_EQ(meshes.size(), 1u);
  const auto& m = meshes[0];
  EXPECT_GT(m.indices.size(), 0u);
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    const auto& a = m.vertices[m.indices[t]].position;
    const auto& b = m.vertices[m.indices[t + 1]].position;
    const auto& c = m.vertices[m.indices[t + 2]].position;
    EXPECT_TRUE(a != b && b != c && a != c);
  }
  for (const auto& v : m.vertices) EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-4f);
}

TEST(Patch, WindingFollowsTheStoredNormals) {
  for (float side : {1.0f, -1.0f}) {
    PatchSpec dome = bumpy(7);
    for (auto& p : dome.controls) p.z = 0.1f * p.z;
    dome.normal = {0, 0, side};
    const BspFile bsp = mapWithPatches({dome});
    const auto m = tessellateSurfaces(bsp)[0];
    int agree = 0, disagree = 0;
    for (size_t t = 0; t < m.indices.size(); t += 3) {
      const auto& a = m.vertices[m.indices[t]];
      const auto& b = m.vertices[m.indices[t + 1]];
      const auto& c = m.vertices[m.indices[t + 2]];
      const glm::vec3 geometric = glm::cross(b.position - a.position, c.position - a.position);
      (glm::dot(geometric, glm::vec3(0, 0, side)) > 0 ? agree : disagree)++;
      EXPECT_GT(glm::dot(a.normal, glm::vec3(0, 0, side)), 0);
    }
    EXPECT_EQ(disagree, 0);
    EXPECT_GT(agree, 0);
  }
}

}  // namespace
}  // namespace q3
