#pragma once
// Bounds-checked reading of glTF accessors (internal to pa_gltf_io).
#include <cstdint>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace pa::gltf::detail {

/// Reads accessor `index` as floats (normalized integers mapped to [0,1] / [-1,1]),
/// `components` values per element. `allowedComponents` lists the accepted element sizes
/// (e.g. {3} for POSITION, {3,4} for COLOR_0). Sparse accessors are applied.
/// Returns count * components floats; `componentsOut` receives the element size.
std::vector<float> readFloats(const tinygltf::Model& model, int index,
                              std::initializer_list<int> allowedComponents,
                              int& componentsOut, const std::string& what);

/// Reads a SCALAR unsigned-integer accessor (UNSIGNED_BYTE/SHORT/INT) as uint32.
std::vector<uint32_t> readIndices(const tinygltf::Model& model, int index, const std::string& what);

/// Number of elements of accessor `index` (checked to exist).
size_t accessorCount(const tinygltf::Model& model, int index, const std::string& what);

}  // namespace pa::gltf::detail
