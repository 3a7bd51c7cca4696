// GlbBuilder: JSON + BIN chunk assembly for binary glTF 2.0.
#include "assets_converter/glb_builder.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <stdexcept>

#include <stb_image_write.h>

namespace pa::converter {
namespace {

constexpr int kFloat = 5126;
constexpr int kUnsignedShort = 5123;
constexpr int kUnsignedInt = 5125;
constexpr uint32_t kGlbMagic = 0x46546C67;    // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;   // "JSON"
constexpr uint32_t kChunkBin = 0x004E4942;    // "BIN\0"

void padTo4(std::vector<std::byte>& bytes, std::byte fill) {
  while (bytes.size() % 4 != 0) bytes.push_back(fill);
}

void appendU32(std::vector<std::byte>& out, uint32_t v) {
  const auto* p = reinterpret_cast<const std::byte*>(&v);   // little-endian host (x86-64)
  out.insert(out.end(), p, p + 4);
}

template <int N, class Vec>
std::pair<nlohmann::json, nlohmann::json> componentBounds(std::span<const Vec> values) {
  std::array<float, N> lo, hi;
  lo.fill(std::numeric_limits<float>::infinity());
  hi.fill(-std::numeric_limits<float>::infinity());
  for (const Vec& v : values)
    for (int c = 0; c < N; ++c) {
      lo[c] = std::min(lo[c], v[c]);
      hi[c] = std::max(hi[c], v[c]);
    }
  return {nlohmann::json(lo), nlohmann::json(hi)};
}

}  // namespace

GlbBuilder::GlbBuilder(std::string generator) {
  doc_["asset"] = {{"version", "2.0"}, {"generator", std::move(generator)}};
}

uint32_t GlbBuilder::append(const char* arrayName, nlohmann::json element) {
  auto& array = doc_[arrayName];
  if (array.is_null()) array = nlohmann::json::array();
  array.push_back(std::move(element));
  return static_cast<uint32_t>(array.size() - 1);
}

uint32_t GlbBuilder::addBufferView(std::span<const std::byte> bytes, BufferTarget target) {
  padTo4(bin_, std::byte{0});
  nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes.size()}};
  if (target != BufferTarget::None) view["target"] = static_cast<int>(target);
  bin_.insert(bin_.end(), bytes.begin(), bytes.end());
  return append("bufferViews", std::move(view));
}

uint32_t GlbBuilder::addAccessor(uint32_t view, int componentType, size_t count, const char* type,
                                 nlohmann::json min, nlohmann::json max) {
  nlohmann::json accessor = {{"bufferView", view}, {"componentType", componentType}, {"count", count}, {"type", type}};
  if (!min.is_null()) accessor["min"] = std::move(min);
  if (!max.is_null()) accessor["max"] = std::move(max);
  return append("accessors", std::move(accessor));
}

uint32_t GlbBuilder::addVec3(std::span<const glm::vec3> values) {
  auto [lo, hi] = componentBounds<3>(values);
  uint32_t view = addBufferView(std::as_bytes(values), BufferTarget::ArrayBuffer);
  return addAccessor(view, kFloat, values.size(), "VEC3", std::move(lo), std::move(hi));
}

uint32_t GlbBuilder::addVec2(std::span<const glm::vec2> values) {
  uint32_t view = addBufferView(std::as_bytes(values), BufferTarget::ArrayBuffer);
  return addAccessor(view, kFloat, values.size(), "VEC2", nullptr, nullptr);
}

uint32_t GlbBuilder::addVec4(std::span<const glm::vec4> values) {
  uint32_t view = addBufferView(std::as_bytes(values), BufferTarget::ArrayBuffer);
  return addAccessor(view, kFloat, values.size(), "VEC4", nullptr, nullptr);
}

uint32_t GlbBuilder::addIndices(std::span<const uint32_t> indices) {
  uint32_t maxIndex = 0;
  for (uint32_t i : indices) maxIndex = std::max(maxIndex, i);
  if (maxIndex < 0xffffu) {   // 65535 is the primitive-restart value: not allowed as an index
    std::vector<uint16_t> narrow(indices.begin(), indices.end());
    uint32_t view = addBufferView(std::as_bytes(std::span<const uint16_t>(narrow)), BufferTarget::ElementArrayBuffer);
    return addAccessor(view, kUnsignedShort, indices.size(), "SCALAR", nullptr, nullptr);
  }
  uint32_t view = addBufferView(std::as_bytes(indices), BufferTarget::ElementArrayBuffer);
  return addAccessor(view, kUnsignedInt, indices.size(), "SCALAR", nullptr, nullptr);
}

std::vector<std::byte> encodePng(uint32_t width, uint32_t height, std::span<const uint8_t> rgba8) {
  std::vector<std::byte> png;
  if (width == 0 || height == 0 || rgba8.size() != size_t(width) * height * 4) return png;
  auto sink = [](void* context, void* data, int size) {
    auto* out = static_cast<std::vector<std::byte>*>(context);
    const auto* p = static_cast<const std::byte*>(data);
    out->insert(out->end(), p, p + size);
  };
  if (!stbi_write_png_to_func(sink, &png, int(width), int(height), 4, rgba8.data(), int(width * 4)))
    png.clear();
  return png;
}

uint32_t GlbBuilder::addPngImage(uint32_t width, uint32_t height, std::span<const uint8_t> rgba8,
                                 const std::string& name) {
  std::vector<std::byte> png = encodePng(width, height, rgba8);
  if (png.empty()) throw std::runtime_error("PNG encoding failed for image '" + name + "'");
  uint32_t view = addBufferView(png, BufferTarget::None);
  return append("images", {{"bufferView", view}, {"mimeType", "image/png"}, {"name", name}});
}

void GlbBuilder::useExtension(const std::string& name, bool required) {
  auto add = [&](const char* key) {
    auto& list = doc_[key];
    if (list.is_null()) list = nlohmann::json::array();
    if (std::find(list.begin(), list.end(), name) == list.end()) list.push_back(name);
  };
  add("extensionsUsed");
  if (required) add("extensionsRequired");
}

std::vector<std::byte> GlbBuilder::finish() {
  padTo4(bin_, std::byte{0});
  if (!bin_.empty()) doc_["buffers"] = nlohmann::json::array({{{"byteLength", bin_.size()}}});
  if (!doc_.contains("scene") && doc_.contains("scenes")) doc_["scene"] = 0;

  const std::string text = doc_.dump();
  std::vector<std::byte> jsonChunk(reinterpret_cast<const std::byte*>(text.data()),
                                   reinterpret_cast<const std::byte*>(text.data()) + text.size());
  padTo4(jsonChunk, std::byte{' '});   // the spec pads JSON with spaces

  std::vector<std::byte> out;
  const size_t total = 12 + 8 + jsonChunk.size() + (bin_.empty() ? 0 : 8 + bin_.size());
  if (total > std::numeric_limits<uint32_t>::max()) throw std::runtime_error("glb larger than 4 GiB");
  out.reserve(total);
  appendU32(out, kGlbMagic);
  appendU32(out, 2);
  appendU32(out, static_cast<uint32_t>(total));
  appendU32(out, static_cast<uint32_t>(jsonChunk.size()));
  appendU32(out, kChunkJson);
  out.insert(out.end(), jsonChunk.begin(), jsonChunk.end());
  if (!bin_.empty()) {
    appendU32(out, static_cast<uint32_t>(bin_.size()));
    appendU32(out, kChunkBin);
    out.insert(out.end(), bin_.begin(), bin_.end());
  }
  return out;
}

}  // namespace pa::converter
