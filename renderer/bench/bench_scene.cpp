#include "renderer/bench/bench_scene.h"

#include <charconv>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "renderer/gltf_io/gltf_loader.h"

namespace pa::bench {

BenchCamera cameraFromBounds(const Bounds& bounds) {
  const glm::vec3 center = bounds.center();
  const glm::vec3 extent = bounds.max - bounds.min;
  BenchCamera camera;
  // Inside-looking view for a game map is better, but for a generic scene look from a corner.
  camera.origin = center + glm::vec3(0.35f, 0.25f, 0.9f) * extent;
  camera.forward = glm::normalize(center - camera.origin);
  camera.up = std::abs(camera.forward.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
  return camera;
}

BenchScene loadGltfScene(const std::string& path) {
  gltf::LoadOptions options;
  options.decodeImages = false;
  const gltf::GltfScene scene = gltf::loadScene(path, options);
  const gltf::TriangleSoup soup = gltf::flattenTriangles(scene);
  BenchScene out;
  out.name = path;
  out.gltfPath = path;
  out.mesh.positions = soup.positions;
  out.mesh.indices = soup.indices;
  if (out.mesh.triangleCount() == 0) throw std::runtime_error(path + ": no triangles in the default scene");
  if (!scene.cameras.empty()) {
    const gltf::GltfCamera& c = scene.cameras.front();
    out.camera = {c.origin, c.forward, c.up, c.yfov};
    out.cameraFromFile = true;
  } else {
    out.camera = cameraFromBounds(out.mesh.bounds());
  }
  return out;
}

BenchScene makeSyntheticScene(const std::string& spec) {
  const auto colon = spec.find(':');
  uint32_t count = 0;
  if (colon == std::string::npos ||
      std::from_chars(spec.data() + colon + 1, spec.data() + spec.size(), count).ec != std::errc() || count == 0)
    throw std::invalid_argument("--synthetic expects soup:N, sphere:N or thin:N, got '" + spec + "'");
  const std::string kind = spec.substr(0, colon);
  BenchScene out;
  out.name = spec;
  if (kind == "soup") out.mesh = testing::makeTriangleSoup(count, 1);
  else if (kind == "sphere") out.mesh = testing::makeSphere(count);
  else if (kind == "thin") out.mesh = testing::makeThinTriangles(count, 2);
  else throw std::invalid_argument("--synthetic: unknown scene kind '" + kind + "'");
  out.camera = cameraFromBounds(out.mesh.bounds());
  return out;
}

}  // namespace pa::bench
