#pragma once
// Reads a .gltf/.glb file into a tinygltf::Model (internal to pa_gltf_io).
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace pa::gltf::detail {

/// Parses `path` (JSON .gltf or binary .glb, detected by content). Images are decoded to
/// RGBA8 when decodeImages is set; images that fail to decode are left empty with a warning.
/// Throws std::runtime_error naming the file on any parse error.
tinygltf::Model readModel(const std::filesystem::path& path, bool decodeImages,
                          std::vector<std::string>& warnings);

/// Parses file bytes as readModel(path) does; `name` labels messages. External URIs resolve
/// against `baseDir`; with an empty baseDir nothing is read from disk (external URIs fail).
tinygltf::Model readModel(std::span<const unsigned char> bytes, const std::string& name,
                          const std::filesystem::path& baseDir, bool decodeImages,
                          std::vector<std::string>& warnings);

}  // namespace pa::gltf::detail
