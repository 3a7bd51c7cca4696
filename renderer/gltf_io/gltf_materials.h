#pragma once
// Images, textures, materials and extras of a glTF model (internal to pa_gltf_io).
#include <tiny_gltf.h>

#include "renderer/gltf_io/gltf_loader.h"

namespace pa::gltf::detail {

/// Converts a glTF `extras` value to text entries (nested objects flattened to dotted keys).
Extras convertExtras(const tinygltf::Value& extras);

/// Fills scene.images, scene.textures and scene.materials from the model (indices checked).
void convertMaterials(const tinygltf::Model& model, const LoadOptions& options, GltfScene& scene);

}  // namespace pa::gltf::detail
