// Bounds-checked accessor reading: every view, buffer, offset, stride and count is checked
// against the actual buffer sizes before a single byte is read.
#include "renderer/gltf_io/gltf_accessor.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <tiny_gltf.h>

namespace pa::gltf::detail {
namespace {

/// Refuses absurd element counts before allocating (a hostile count with no bufferView).
constexpr size_t kMaxElements = size_t{1} << 28;

[[noreturn]] void fail(const std::string& what, const std::string& message) {
  throw std::runtime_error(what + ": " + message);
}

size_t componentBytes(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

int componentsPerElement(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

template <typename T>
T loadUnaligned(const uint8_t* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

float decodeComponent(const uint8_t* p, int componentType, bool normalized) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const float v = loadUnaligned<int8_t>(p);
      return normalized ? std::max(v / 127.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const float v = loadUnaligned<uint8_t>(p);
      return normalized ? v / 255.0f : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const float v = loadUnaligned<int16_t>(p);
      return normalized ? std::max(v / 32767.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const float v = loadUnaligned<uint16_t>(p);
      return normalized ? v / 65535.0f : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return static_cast<float>(loadUnaligned<uint32_t>(p));
    default:
      return loadUnaligned<float>(p);
  }
}

uint32_t decodeUnsigned(const uint8_t* p, int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return loadUnaligned<uint8_t>(p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return loadUnaligned<uint16_t>(p);
    default: return loadUnaligned<uint32_t>(p);
  }
}

/// A validated strided range inside a buffer: element i lives at data + i * stride.
struct StridedRange {
  const uint8_t* data = nullptr;
  size_t stride = 0;
};

/// Validates that `count` elements of `elementBytes`, starting `offset` bytes into buffer
/// view `viewIndex`, lie inside both the view and its buffer.
StridedRange checkedRange(const tinygltf::Model& model, int viewIndex, size_t offset, size_t count,
                          size_t elementBytes, bool allowStride, const std::string& what) {
  if (viewIndex < 0 || static_cast<size_t>(viewIndex) >= model.bufferViews.size())
    fail(what, "bufferView " + std::to_string(viewIndex) + " out of range (file has " +
                   std::to_string(model.bufferViews.size()) + " bufferViews)");
  const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(viewIndex)];
  const std::string viewName = "bufferViews[" + std::to_string(viewIndex) + "]";
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
    fail(what, viewName + ".buffer " + std::to_string(view.buffer) + " out of range (file has " +
                   std::to_string(model.buffers.size()) + " buffers)");
  const size_t bufferSize = model.buffers[static_cast<size_t>(view.buffer)].data.size();
  size_t viewEnd = 0;
  if (__builtin_add_overflow(view.byteOffset, view.byteLength, &viewEnd) || viewEnd > bufferSize)
    fail(what, viewName + " (byteOffset " + std::to_string(view.byteOffset) + " + byteLength " +
                   std::to_string(view.byteLength) + ") exceeds buffer " +
                   std::to_string(view.buffer) + " of " + std::to_string(bufferSize) + " bytes");
  size_t stride = elementBytes;
  if (allowStride && view.byteStride != 0) {
    if (view.byteStride < elementBytes)
      fail(what, viewName + ".byteStride " + std::to_string(view.byteStride) +
                     " is smaller than the element size " + std::to_string(elementBytes));
    stride = view.byteStride;
  }
  if (count == 0) return {nullptr, stride};
  size_t span = 0;
  size_t end = 0;
  if (__builtin_mul_overflow(count - 1, stride, &span) || __builtin_add_overflow(span, elementBytes, &span) ||
      __builtin_add_overflow(span, offset, &end) || end > view.byteLength)
    fail(what, std::to_string(count) + " elements of " + std::to_string(elementBytes) +
                   " bytes at byteOffset " + std::to_string(offset) + " overrun " + viewName +
                   " (byteLength " + std::to_string(view.byteLength) + ")");
  const uint8_t* base = model.buffers[static_cast<size_t>(view.buffer)].data.data();
  return {base + view.byteOffset + offset, stride};
}

const tinygltf::Accessor& checkedAccessor(const tinygltf::Model& model, int index, const std::string& what) {
  if (index < 0 || static_cast<size_t>(index) >= model.accessors.size())
    fail(what, "accessor " + std::to_string(index) + " out of range (file has " +
                   std::to_string(model.accessors.size()) + " accessors)");
  const tinygltf::Accessor& accessor = model.accessors[static_cast<size_t>(index)];
  if (accessor.count > kMaxElements)
    fail(what, "accessors[" + std::to_string(index) + "].count " + std::to_string(accessor.count) +
                   " is too large");
  return accessor;
}

}  // namespace

size_t accessorCount(const tinygltf::Model& model, int index, const std::string& what) {
  return checkedAccessor(model, index, what).count;
}

std::vector<float> readFloats(const tinygltf::Model& model, int index,
                              std::initializer_list<int> allowedComponents, int& componentsOut,
                              const std::string& what) {
  const tinygltf::Accessor& accessor = checkedAccessor(model, index, what);
  const std::string name = what + " (accessors[" + std::to_string(index) + "])";
  const size_t bytes = componentBytes(accessor.componentType);
  const int components = accessor.type == TINYGLTF_TYPE_SCALAR || accessor.type == TINYGLTF_TYPE_VEC2 ||
                                 accessor.type == TINYGLTF_TYPE_VEC3 || accessor.type == TINYGLTF_TYPE_VEC4
                             ? componentsPerElement(accessor.type)
                             : 0;
  if (bytes == 0) fail(name, "invalid componentType " + std::to_string(accessor.componentType));
  if (std::find(allowedComponents.begin(), allowedComponents.end(), components) == allowedComponents.end())
    fail(name, "unexpected accessor type " + std::to_string(accessor.type) + " (" +
                   std::to_string(components) + " components)");
  componentsOut = components;
  const size_t elementBytes = bytes * static_cast<size_t>(components);
  std::vector<float> out(accessor.count * static_cast<size_t>(components), 0.0f);

  auto decodeRange = [&](const StridedRange& range, size_t element, size_t source) {
    const uint8_t* p = range.data + source * range.stride;
    for (int c = 0; c < components; ++c)
      out[element * components + c] =
          decodeComponent(p + c * bytes, accessor.componentType, accessor.normalized);
  };
  if (accessor.bufferView >= 0) {
    const StridedRange range = checkedRange(model, accessor.bufferView, accessor.byteOffset, accessor.count,
                                            elementBytes, true, name);
    for (size_t i = 0; i < accessor.count; ++i) decodeRange(range, i, i);
  }
  if (accessor.sparse.isSparse) {
    const auto& sparse = accessor.sparse;
    if (sparse.count < 0 || static_cast<size_t>(sparse.count) > accessor.count)
      fail(name, "sparse.count " + std::to_string(sparse.count) + " exceeds accessor count " +
                     std::to_string(accessor.count));
    const size_t indexBytes = componentBytes(sparse.indices.componentType);
    if (indexBytes == 0 || sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
        sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT ||
        sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT)
      fail(name, "invalid sparse.indices.componentType " + std::to_string(sparse.indices.componentType));
    if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0)
      fail(name, "negative sparse byteOffset");
    const size_t count = static_cast<size_t>(sparse.count);
    const StridedRange indices = checkedRange(model, sparse.indices.bufferView,
                                              static_cast<size_t>(sparse.indices.byteOffset), count,
                                              indexBytes, false, name + " sparse.indices");
    const StridedRange values = checkedRange(model, sparse.values.bufferView,
                                             static_cast<size_t>(sparse.values.byteOffset), count,
                                             elementBytes, false, name + " sparse.values");
    for (size_t i = 0; i < count; ++i) {
      const uint32_t target = decodeUnsigned(indices.data + i * indexBytes, sparse.indices.componentType);
      if (target >= accessor.count)
        fail(name, "sparse index " + std::to_string(target) + " out of range (count " +
                       std::to_string(accessor.count) + ")");
      decodeRange(values, target, i);
    }
  }
  for (size_t i = 0; i < out.size(); ++i)
    if (!std::isfinite(out[i]))
      fail(name, "non-finite value at element " + std::to_string(i / static_cast<size_t>(components)));
  return out;
}

std::vector<uint32_t> readIndices(const tinygltf::Model& model, int index, const std::string& what) {
  const tinygltf::Accessor& accessor = checkedAccessor(model, index, what);
  const std::string name = what + " (accessors[" + std::to_string(index) + "])";
  if (accessor.type != TINYGLTF_TYPE_SCALAR) fail(name, "indices must be SCALAR");
  if (accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    fail(name, "indices componentType " + std::to_string(accessor.componentType) +
                   " is not an unsigned integer type");
  if (accessor.sparse.isSparse) fail(name, "sparse index accessors are not supported");
  if (accessor.bufferView < 0) fail(name, "index accessor has no bufferView");
  const size_t bytes = componentBytes(accessor.componentType);
  // Index data must be tightly packed (glTF forbids byteStride on index views).
  const StridedRange range =
      checkedRange(model, accessor.bufferView, accessor.byteOffset, accessor.count, bytes, false, name);
  std::vector<uint32_t> out(accessor.count);
  for (size_t i = 0; i < accessor.count; ++i)
    out[i] = decodeUnsigned(range.data + i * bytes, accessor.componentType);
  return out;
}

}  // namespace pa::gltf::detail
