// ModelBuilder: appends typed arrays to buffer 0 and writes through tinygltf's writer.
#include "renderer/gltf_io/gltf_builder.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include <glm/common.hpp>

namespace pa::gltf {

ModelBuilder::ModelBuilder() {
  model_.asset.version = "2.0";
  model_.asset.generator = "PathArena pa::gltf::ModelBuilder";
  model_.buffers.emplace_back();
  model_.scenes.emplace_back();
  model_.defaultScene = 0;
}

int ModelBuilder::addView(std::span<const uint8_t> bytes, size_t byteStride, int target) {
  std::vector<unsigned char>& data = model_.buffers[0].data;
  data.resize((data.size() + 3) & ~size_t{3}, 0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = bytes.size();
  view.byteStride = byteStride;
  view.target = target;
  data.insert(data.end(), bytes.begin(), bytes.end());
  model_.bufferViews.push_back(view);
  return static_cast<int>(model_.bufferViews.size() - 1);
}

int ModelBuilder::addAccessor(int view, size_t byteOffset, int componentType, int type, size_t count,
                              bool normalized) {
  tinygltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.byteOffset = byteOffset;
  accessor.componentType = componentType;
  accessor.type = type;
  accessor.count = count;
  accessor.normalized = normalized;
  model_.accessors.push_back(accessor);
  return static_cast<int>(model_.accessors.size() - 1);
}

namespace {
template <typename T>
std::span<const uint8_t> asBytes(std::span<const T> values) {
  return {reinterpret_cast<const uint8_t*>(values.data()), values.size_bytes()};
}
}  // namespace

int ModelBuilder::addVec3(std::span<const glm::vec3> values, bool withBounds) {
  const int view = addView(asBytes(values), 0, TINYGLTF_TARGET_ARRAY_BUFFER);
  const int accessor = addAccessor(view, 0, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, values.size());
  if (withBounds && !values.empty()) {
    glm::vec3 lo = values[0], hi = values[0];
    for (const glm::vec3& v : values) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
    model_.accessors[static_cast<size_t>(accessor)].minValues = {lo.x, lo.y, lo.z};
    model_.accessors[static_cast<size_t>(accessor)].maxValues = {hi.x, hi.y, hi.z};
  }
  return accessor;
}

int ModelBuilder::addVec2(std::span<const glm::vec2> values) {
  const int view = addView(asBytes(values), 0, TINYGLTF_TARGET_ARRAY_BUFFER);
  return addAccessor(view, 0, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, values.size());
}

int ModelBuilder::addVec4(std::span<const glm::vec4> values) {
  const int view = addView(asBytes(values), 0, TINYGLTF_TARGET_ARRAY_BUFFER);
  return addAccessor(view, 0, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, values.size());
}

int ModelBuilder::addIndices(std::span<const uint32_t> indices, int componentType) {
  std::vector<uint8_t> bytes;
  for (uint32_t index : indices) {
    if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
      if (index > 0xffu) throw std::invalid_argument("ModelBuilder::addIndices: index does not fit a byte");
      bytes.push_back(static_cast<uint8_t>(index));
    } else if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
      if (index > 0xffffu) throw std::invalid_argument("ModelBuilder::addIndices: index does not fit a short");
      const uint16_t value = static_cast<uint16_t>(index);
      bytes.insert(bytes.end(), reinterpret_cast<const uint8_t*>(&value), reinterpret_cast<const uint8_t*>(&value) + 2);
    } else {
      bytes.insert(bytes.end(), reinterpret_cast<const uint8_t*>(&index), reinterpret_cast<const uint8_t*>(&index) + 4);
    }
  }
  const int view = addView(bytes, 0, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  return addAccessor(view, 0, componentType, TINYGLTF_TYPE_SCALAR, indices.size());
}

int ModelBuilder::addTexture(const std::string& name, uint32_t width, uint32_t height,
                             std::span<const uint8_t> rgba8, bool clamp) {
  if (rgba8.size() != size_t{width} * height * 4)
    throw std::invalid_argument("ModelBuilder::addTexture: pixel array size mismatch");
  tinygltf::Image image;
  image.name = name;
  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);
  image.component = 4;
  image.bits = 8;
  image.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image.mimeType = "image/png";
  image.image.assign(rgba8.begin(), rgba8.end());
  model_.images.push_back(std::move(image));
  tinygltf::Sampler sampler;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  sampler.wrapS = sampler.wrapT = clamp ? TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE : TINYGLTF_TEXTURE_WRAP_REPEAT;
  model_.samplers.push_back(sampler);
  tinygltf::Texture texture;
  texture.name = name;
  texture.source = static_cast<int>(model_.images.size() - 1);
  texture.sampler = static_cast<int>(model_.samplers.size() - 1);
  model_.textures.push_back(texture);
  return static_cast<int>(model_.textures.size() - 1);
}

int ModelBuilder::addNode(tinygltf::Node node, int parent) {
  model_.nodes.push_back(std::move(node));
  const int index = static_cast<int>(model_.nodes.size() - 1);
  if (parent >= 0) model_.nodes.at(static_cast<size_t>(parent)).children.push_back(index);
  else model_.scenes[0].nodes.push_back(index);
  return index;
}

void ModelBuilder::writeGltf(const std::filesystem::path& path) { write(path, false); }
void ModelBuilder::writeGlb(const std::filesystem::path& path) { write(path, true); }

void ModelBuilder::write(const std::filesystem::path& path, bool binary) {
  model_.buffers[0].data.resize((model_.buffers[0].data.size() + 3) & ~size_t{3}, 0);
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToFile(&model_, path.string(), true, true, !binary, binary))
    throw std::runtime_error(path.string() + ": cannot write glTF");
}

}  // namespace pa::gltf
