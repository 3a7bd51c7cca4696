// Embree 3 as the oracle for our BVH on real data: the triangles of every OpenArena map
// installed (all models, patches tessellated), random rays from inside the map and from the
// spawn points. Closest hits agree (t within 1e-4 relative, same triangle except at shared
// edges/vertices) and any-hit answers on segments agree; see renderer/bvh/tests/oracle_compare.h.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/bsp/entities.h"
#include "port/q3formats/bsp/tessellate.h"
#include "port/q3formats/bsp/tools/pk3_maps.h"
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/testing/embree_oracle.h"
#include "renderer/bvh/tests/oracle_compare.h"

namespace pa::testing {
namespace {

constexpr uint32_t kRaysPerMap = 1u << 17;        // 131,072 per map in AllMaps
constexpr uint32_t kRaysLargeRun = 1u << 20;      // 1,048,576 in LargeMaps
constexpr uint32_t kChunk = 1u << 12;             // rays per parallel task
const char* const kGameDir = "/usr/share/games/openarena";

/// One .bsp inside one .pk3.
struct MapRef {
  std::string archive, path;
};

/// Every .bsp in every .pk3 of baseoa/ and missionpack/ (empty when OpenArena is not installed).
std::vector<MapRef> installedMaps() {
  std::vector<std::string> archives;
  for (const char* dir : {"baseoa", "missionpack"}) {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(std::string(kGameDir) + "/" + dir, ec))
      if (entry.path().extension() == ".pk3") archives.push_back(entry.path().string());
  }
  std::sort(archives.begin(), archives.end());
  std::vector<MapRef> maps;
  q3::tools::Pk3Reader reader("real_map_oracle_test");
  for (const std::string& archive : archives) {
    reader.mount(archive);
    for (const std::string& path : reader.listMaps()) maps.push_back({archive, path});
  }
  return maps;
}

/// Test name from archive and map, e.g. "pak1_maps_oa_dm1".
std::string mapTestName(const ::testing::TestParamInfo<MapRef>& info) {
  std::string name = std::filesystem::path(info.param.archive).stem().string() + "_" +
                     std::filesystem::path(info.param.path).stem().string();
  for (char& c : name) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

/// All tessellated surfaces of all models, merged into one triangle list; spawn eyes too.
TestMesh loadMapTriangles(const MapRef& map, std::vector<glm::vec3>& spawnEyes) {
  q3::tools::Pk3Reader reader("real_map_oracle_test");
  reader.mount(map.archive);
  const q3::BspFile bsp = q3::parseBsp(reader.read(map.path), map.path);
  TestMesh mesh;
  for (const q3::SurfaceMesh& surface : q3::tessellateSurfaces(bsp)) {
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    for (const q3::MeshVertex& v : surface.vertices) mesh.positions.push_back(v.position);
    for (uint32_t i : surface.indices) mesh.indices.push_back(base + i);
  }
  for (const q3::SpawnCamera& spawn : q3::readSpawnCameras(q3::parseEntities(bsp.entities, map.path)))
    spawnEyes.push_back(spawn.eye);
  return mesh;
}

/// Rays: three quarters from uniform points in the map bounds, one quarter from spawn eyes,
/// all with uniform directions; tmin 0, tmax infinite.
std::vector<Ray> makeMapRays(const Bounds& bounds, const std::vector<glm::vec3>& spawnEyes, uint32_t count,
                             uint32_t seed) {
  std::vector<Ray> rays = makeRandomRays(bounds, count, seed);
  for (uint32_t i = 0; !spawnEyes.empty() && i < count; i += 4) rays[i].origin = spawnEyes[(i / 4) % spawnEyes.size()];
  return rays;
}

/// Whether point p lies on triangle `prim` within `tol` (off its plane and outside its edges).
bool onTriangle(const TestMesh& mesh, uint32_t prim, glm::vec3 p, float tol) {
  const glm::vec3 v[3] = {mesh.positions[mesh.indices[3 * prim]], mesh.positions[mesh.indices[3 * prim + 1]],
                          mesh.positions[mesh.indices[3 * prim + 2]]};
  const glm::vec3 n = glm::cross(v[1] - v[0], v[2] - v[0]);
  const float area2 = glm::length(n);
  if (area2 == 0.0f || std::fabs(glm::dot(p - v[0], n)) > tol * area2) return false;
  for (int k = 0; k < 3; ++k) {
    const glm::vec3 edge = v[(k + 1) % 3] - v[k];
    if (glm::dot(glm::cross(edge, p - v[k]), n) < -tol * area2 * glm::length(edge)) return false;
  }
  return true;
}

/// Two different triangles hit at the same t where each hit point lies on the other triangle:
/// overlapping coplanar or duplicated triangles (common in maps), or a shared edge/vertex.
bool sameSurfacePoint(const TestMesh& mesh, bool hitA, const Hit& a, bool hitB, const Hit& b, float sceneScale) {
  if (!hitA || !hitB || a.prim == b.prim) return false;
  const float tol = 1e-4f * b.t + 1e-5f * sceneScale;
  return std::fabs(a.t - b.t) <= tol && onTriangle(mesh, b.prim, hitPoint(mesh, a), tol) &&
         onTriangle(mesh, a.prim, hitPoint(mesh, b), tol);
}

/// One side hit at the ray's start (t ~ tmin = 0, origin on a surface), the other did not:
/// Embree's interval excludes tmin, ours includes it.
bool hitAtRayStart(bool hitA, const Hit& a, bool hitB, const Hit& b, float sceneScale) {
  const float tol = 1e-5f * sceneScale;
  return (hitA && a.t <= tol && !(hitB && b.t <= tol)) || (hitB && b.t <= tol && !(hitA && a.t <= tol));
}

/// Any-hit disagreement is acceptable only when a closest hit sits at the segment's start or end (within
/// the closest-hit tolerance) or on an edge of its triangle.
void compareOcclusion(OracleTally& tally, bool ours, bool embree, const Hit& oursClosest, const Hit& embreeClosest,
                      float segmentEnd, float sceneScale) {
  ++tally.rays;
  if (ours == embree) return;
  bool explained = false;
  for (const Hit& h : {oursClosest, embreeClosest}) {
    const bool atEnd = std::fabs(h.t - segmentEnd) <= 1e-4f * segmentEnd + 1e-5f * sceneScale;
    const bool atStart = h.t <= 1e-5f * sceneScale;
    explained = explained || atEnd || atStart || (h.t <= segmentEnd && minBarycentric(h) < 1e-3f);
  }
  if (explained) {
    ++tally.edgeCases;
  } else if (++tally.unexplained == 1) {
    tally.firstProblem = std::string("occlusion disagrees: ours ") + (ours ? "occluded" : "clear") + ", segment end " +
                         std::to_string(segmentEnd) + ", closest t ours " + std::to_string(oursClosest.t) +
                         " embree " + std::to_string(embreeClosest.t);
  }
}

/// Adds b's counts to a, keeping a's first problem if it has one.
void merge(OracleTally& a, const OracleTally& b) {
  a.rays += b.rays; a.hits += b.hits; a.sameHits += b.sameHits; a.edgeCases += b.edgeCases;
  a.unexplained += b.unexplained;
  if (a.firstProblem.empty()) a.firstProblem = b.firstProblem;
}

/// Prints the first disagreeing ray exactly and the triangles both sides hit.
void describeRay(const TestMesh& mesh, const Ray& ray, const Hit& ours, const Hit& embree) {
  std::printf("  ray origin (%.9g %.9g %.9g) dir (%.9g %.9g %.9g) tmax %.9g\n", ray.origin.x, ray.origin.y,
              ray.origin.z, ray.dir.x, ray.dir.y, ray.dir.z, ray.tmax);
  for (const Hit* h : {&ours, &embree}) {
    if (h->prim >= mesh.triangleCount()) continue;
    std::printf("  %s prim %u t %.9g uv %.9g %.9g:", h == &ours ? "ours  " : "embree", h->prim, h->t, h->u, h->v);
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = mesh.positions[mesh.indices[3 * h->prim + k]];
      std::printf(" (%.9g %.9g %.9g)", p.x, p.y, p.z);
    }
    std::printf("\n");
  }
}

/// oa_dm1 and the map with the most triangles (tessellates every map): the >= 1M ray run.
std::vector<MapRef> largeRunMaps() {
  std::vector<MapRef> out;
  MapRef largest;
  uint32_t mostTriangles = 0;
  for (const MapRef& map : installedMaps()) {
    if (map.path == "maps/oa_dm1.bsp" && out.empty()) out.push_back(map);
    std::vector<glm::vec3> spawns;
    const uint32_t triangles = loadMapTriangles(map, spawns).triangleCount();
    if (triangles > mostTriangles) mostTriangles = triangles, largest = map;
  }
  if (mostTriangles > 0) out.push_back(largest);
  return out;
}

/// Builds both BVHs over the map, traces `rayCount` rays through both, asserts no unexplained
/// disagreement and prints the tallies.
void runMapOracle(const MapRef& map, uint32_t rayCount) {
  std::vector<glm::vec3> spawnEyes;
  const TestMesh mesh = loadMapTriangles(map, spawnEyes);
  ASSERT_GT(mesh.triangleCount(), 0u);
  Blas blas;
  blas.build(mesh.input());
  const EmbreeDevice device;
  EmbreeScene embree(device);
  embree.addMesh(mesh);
  embree.commit();
  const Bounds bounds = blas.bounds();
  const float scale = glm::length(bounds.max - bounds.min);
  const std::vector<Ray> rays = makeMapRays(bounds, spawnEyes, rayCount, 0x5eed + rayCount);
  // Segment ends uniform in [0, 2 * closest t] (or the map size on a miss): half are blocked.
  std::mt19937 rng(rayCount);
  std::vector<float> fractions(rays.size());
  for (float& f : fractions) f = std::uniform_real_distribution<float>(0.0f, 2.0f)(rng);
  std::vector<OracleTally> closest(rays.size() / kChunk), anyHit(rays.size() / kChunk);
  std::vector<uint32_t> firstBad(closest.size(), UINT32_MAX);
  std::vector<uint64_t> coincident(closest.size(), 0);
  tbb::parallel_for(size_t(0), closest.size(), [&](size_t c) {
    for (uint32_t i = uint32_t(c) * kChunk; i < uint32_t(c + 1) * kChunk; ++i) {
      Ray a = rays[i], b = rays[i];
      Hit ha, hb;
      const bool hitA = blas.intersect(a, ha), hitB = embree.intersect(b, hb);
      if (sameSurfacePoint(mesh, hitA, ha, hitB, hb, scale))
        ++closest[c].rays, ++closest[c].hits, ++coincident[c];
      else if (hitAtRayStart(hitA, ha, hitB, hb, scale))
        ++closest[c].rays, ++closest[c].edgeCases;
      else
        compareClosest(closest[c], hitA, ha, hitB, hb, scale);
      Ray segment = rays[i];
      segment.tmax = fractions[i] * (hitB ? hb.t : 0.5f * scale);
      compareOcclusion(anyHit[c], blas.occluded(segment), embree.occluded(segment), ha, hb, segment.tmax, scale);
      if (firstBad[c] == UINT32_MAX && closest[c].unexplained + anyHit[c].unexplained > 0) firstBad[c] = i;
    }
  });
  OracleTally closestTotal, anyHitTotal;
  uint64_t coincidentTotal = 0;
  for (size_t c = 0; c < closest.size(); ++c)
    merge(closestTotal, closest[c]), merge(anyHitTotal, anyHit[c]), coincidentTotal += coincident[c];
  std::printf("%s:%s  %u tris, %zu spawns, %llu rays: %llu hits, %llu same, %llu other triangle at the same point, "
              "%llu edge cases, %llu bad; "
              "any-hit %llu edge cases, %llu bad\n", map.archive.c_str(), map.path.c_str(), mesh.triangleCount(),
              spawnEyes.size(), (unsigned long long)closestTotal.rays, (unsigned long long)closestTotal.hits,
              (unsigned long long)closestTotal.sameHits, (unsigned long long)coincidentTotal, (unsigned long long)closestTotal.edgeCases,
              (unsigned long long)closestTotal.unexplained, (unsigned long long)anyHitTotal.edgeCases,
              (unsigned long long)anyHitTotal.unexplained);
  for (uint32_t i : firstBad) {
    if (i == UINT32_MAX) continue;
    Ray a = rays[i], b = rays[i];
    Hit ha, hb;
    blas.intersect(a, ha), embree.intersect(b, hb);
    describeRay(mesh, rays[i], ha, hb);
    break;
  }
  EXPECT_EQ(closestTotal.unexplained, 0u) << closestTotal.firstProblem;
  EXPECT_EQ(anyHitTotal.unexplained, 0u) << anyHitTotal.firstProblem;
}

class AllMaps : public ::testing::TestWithParam<MapRef> {};
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(AllMaps);

TEST_P(AllMaps, OurBvhAgreesWithEmbree) { runMapOracle(GetParam(), kRaysPerMap); }
TEST(LargeMaps, OurBvhAgreesWithEmbreeOnAMillionRays) {
  const std::vector<MapRef> maps = largeRunMaps();
  if (maps.empty()) GTEST_SKIP() << "no OpenArena maps under " << kGameDir;
  for (const MapRef& map : maps) {
    SCOPED_TRACE(map.archive + ":" + map.path);
    runMapOracle(map, kRaysLargeRun);
  }
}

INSTANTIATE_TEST_SUITE_P(OpenArena, AllMaps, ::testing::ValuesIn(installedMaps()), mapTestName);

/// Without OpenArena installed the suites above are empty; this says so instead of passing silently.
TEST(RealMapOracle, OpenArenaIsInstalled) {
  if (installedMaps().empty()) GTEST_SKIP() << "no OpenArena maps under " << kGameDir;
}

}  // namespace
}  // namespace pa::testing
