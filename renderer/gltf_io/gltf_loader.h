#pragma once
// glTF 2.0 (.gltf with embedded or external buffers, .glb) import through tinygltf.
// Every index, offset and count in the file is checked; malformed input throws
// std::runtime_error whose message names the file and the offending field.
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>

#include "renderer/gltf_io/gltf_scene.h"

namespace pa::gltf {

/// Knobs of the importer.
struct LoadOptions {
  bool decodeImages = true;     ///< False: skip image decoding (geometry-only users).
  /// Multiplies every photometric quantity (light candela/lux, emissive strength) to give
  /// the renderer's radiometric units; one factor for all keeps lights and emitters balanced.
  float lightUnitScale = 1.0f;
  int scene = -1;               ///< Scene to import; -1 = the file's default scene (or 0).
};

/// Loads a whole scene: meshes, instances, materials, textures, lights, cameras.
GltfScene loadScene(const std::filesystem::path& path, const LoadOptions& options = {});

/// Loads a whole scene from the bytes of a .gltf or .glb; `name` labels error messages.
/// External buffer/image URIs resolve against `baseDir`; with an empty baseDir no file is
/// read (such URIs fail: data URIs and the GLB chunk still work).
GltfScene loadSceneFromMemory(std::span<const std::byte> bytes, const std::string& name,
                              const std::filesystem::path& baseDir = {}, const LoadOptions& options = {});

/// Loads the world-space triangles of every mesh primitive of the default scene
/// (node transforms applied, strips and fans converted, mirrored instances re-wound).
TriangleSoup loadTriangles(const std::filesystem::path& path);

/// Flattens a loaded scene's instances into one world-space triangle soup.
TriangleSoup flattenTriangles(const GltfScene& scene);

}  // namespace pa::gltf
