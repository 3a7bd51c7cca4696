// File reading, GLB header validation and image decoding for the glTF importer.
#include "renderer/gltf_io/gltf_model_reader.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <span>
#include <stdexcept>

#include <stb_image.h>

#include "renderer/image_codecs/jpeg_decode.h"

namespace pa::gltf::detail {
namespace {

/// tinygltf takes 32-bit sizes; glTF binary is limited to 4 GiB anyway.
constexpr uint64_t kMaxFileBytes = 0xfffffff0ull;
/// Refuse decoded images larger than this many pixels (hostile headers).
constexpr uint64_t kMaxImagePixels = uint64_t{1} << 26;

std::vector<unsigned char> readFileBytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file) throw std::runtime_error(path.string() + ": cannot open file");
  const std::streamoff size = file.tellg();
  if (size < 0) throw std::runtime_error(path.string() + ": cannot determine file size");
  if (static_cast<uint64_t>(size) > kMaxFileBytes) throw std::runtime_error(path.string() + ": file too large");
  std::vector<unsigned char> bytes(static_cast<size_t>(size));
  file.seekg(0);
  if (!file.read(reinterpret_cast<char*>(bytes.data()), size))
    throw std::runtime_error(path.string() + ": read error");
  return bytes;
}

uint32_t readLittleEndian32(const unsigned char* p) {
  return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
}

/// Checks the GLB container (header, chunk lengths) so that truncation gets a precise message.
void validateGlbContainer(std::span<const unsigned char> bytes, const std::string& name) {
  if (bytes.size() < 20) throw std::runtime_error(name + ": truncated GLB (" + std::to_string(bytes.size()) +
                                                  " bytes, header needs 20)");
  const uint32_t version = readLittleEndian32(bytes.data() + 4);
  const uint32_t length = readLittleEndian32(bytes.data() + 8);
  const uint32_t jsonLength = readLittleEndian32(bytes.data() + 12);
  const uint32_t jsonType = readLittleEndian32(bytes.data() + 16);
  if (version != 2) throw std::runtime_error(name + ": GLB version " + std::to_string(version) + " (need 2)");
  if (length > bytes.size())
    throw std::runtime_error(name + ": truncated GLB (header length " + std::to_string(length) +
                             " bytes, file has " + std::to_string(bytes.size()) + ")");
  if (jsonType != 0x4E4F534Au) throw std::runtime_error(name + ": GLB first chunk is not JSON");
  if (20ull + jsonLength > length)
    throw std::runtime_error(name + ": truncated GLB (JSON chunk of " + std::to_string(jsonLength) +
                             " bytes overruns total length " + std::to_string(length) + ")");
  const uint64_t binStart = 20ull + jsonLength;
  if (binStart + 8 <= length) {
    const uint32_t binLength = readLittleEndian32(bytes.data() + binStart);
    if (binStart + 8 + binLength > length)
      throw std::runtime_error(name + ": truncated GLB (BIN chunk of " + std::to_string(binLength) +
                               " bytes overruns total length " + std::to_string(length) + ")");
  }
}

/// Context handed to the image callback.
struct ImageDecodeContext {
  bool decode = true;
  std::vector<std::string>* warnings = nullptr;
  /// Images stored in a buffer view, decoded once the whole file is parsed: tinygltf hands the
  /// callback such an image's bytes without checking the view against its buffer.
  std::vector<int> inBufferViews;
};

/// Decodes `bytes` into `image` as RGBA8 (libjpeg-turbo for JPEG, stb otherwise). An image that
/// cannot be decoded is left empty and reported as a warning.
void decodeImageBytes(tinygltf::Image& image, const int imageIndex, std::span<const unsigned char> bytes,
                      std::vector<std::string>& warnings) {
  image.width = image.height = 0;
  image.image.clear();
  const std::string label = "images[" + std::to_string(imageIndex) + "] \"" + image.name + "\"";
  const std::span<const std::byte> span = std::as_bytes(bytes);
  if (pa::isJpeg(span)) {  // libjpeg-turbo: stb 2.27 has undefined behaviour on corrupt JPEGs
    try {
      const auto [w, h] = pa::jpegSize(span);
      if (w < 1 || h < 1 || static_cast<uint64_t>(w) * static_cast<uint64_t>(h) > kMaxImagePixels)
        throw pa::JpegError(pa::JpegError::Stage::Size, "bad size");
      pa::JpegImage jpeg = pa::decodeJpeg(span, {.maxDimension = 65535});
      image.width = jpeg.width;
      image.height = jpeg.height;
      image.image = std::move(jpeg.rgba);
    } catch (const pa::JpegError& e) {
      warnings.push_back(label + ": cannot decode image (" + e.what() + ")");
    }
    return;
  }
  const int size = static_cast<int>(std::min<size_t>(bytes.size(), INT32_MAX));
  int width = 0, height = 0, channels = 0;
  if (!stbi_info_from_memory(bytes.data(), size, &width, &height, &channels) || width < 1 || height < 1 ||
      static_cast<uint64_t>(width) * static_cast<uint64_t>(height) > kMaxImagePixels) {
    warnings.push_back(label + ": cannot decode image (" +
                       std::string(stbi_failure_reason() ? stbi_failure_reason() : "bad size") + ")");
    return;
  }
  stbi_uc* pixels = stbi_load_from_memory(bytes.data(), size, &width, &height, &channels, 4);
  if (!pixels) {
    warnings.push_back(label + ": cannot decode image (" + std::string(stbi_failure_reason()) + ")");
    return;
  }
  image.width = width;
  image.height = height;
  image.image.assign(pixels, pixels + static_cast<size_t>(width) * static_cast<size_t>(height) * 4);
  stbi_image_free(pixels);
}

/// tinygltf image callback. Never fails the load. Images named by a URI are decoded here (tinygltf
/// owns and sizes those bytes); images in a buffer view are left for decodeBufferViewImages.
bool decodeImage(tinygltf::Image* image, const int imageIndex, std::string*, std::string*, int, int,
                 const unsigned char* bytes, int size, void* userData) {
  auto* context = static_cast<ImageDecodeContext*>(userData);
  image->width = image->height = 0;
  image->component = 4;
  image->bits = 8;
  image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image->image.clear();
  if (!context->decode) return true;
  if (image->bufferView >= 0) {
    context->inBufferViews.push_back(imageIndex);
    return true;
  }
  decodeImageBytes(*image, imageIndex, {bytes, size > 0 ? static_cast<size_t>(size) : 0}, *context->warnings);
  return true;
}

/// Decodes the images stored in buffer views, each after checking its view lies inside its buffer.
void decodeBufferViewImages(tinygltf::Model& model, const std::vector<int>& indices,
                            std::vector<std::string>& warnings) {
  for (const int index : indices) {
    if (index < 0 || static_cast<size_t>(index) >= model.images.size()) continue;
    tinygltf::Image& image = model.images[static_cast<size_t>(index)];
    const auto viewIndex = static_cast<size_t>(image.bufferView);
    if (viewIndex >= model.bufferViews.size()) continue;  // tinygltf has refused the file already
    const tinygltf::BufferView& view = model.bufferViews[viewIndex];
    const size_t bufferBytes = view.buffer >= 0 && static_cast<size_t>(view.buffer) < model.buffers.size()
                                   ? model.buffers[static_cast<size_t>(view.buffer)].data.size()
                                   : 0;
    if (view.byteOffset > bufferBytes || view.byteLength > bufferBytes - view.byteOffset) {
      warnings.push_back("images[" + std::to_string(index) + "] \"" + image.name +
                         "\": cannot decode image (bufferView " + std::to_string(viewIndex) + " of " +
                         std::to_string(view.byteLength) + " bytes at offset " + std::to_string(view.byteOffset) +
                         " overruns its buffer of " + std::to_string(bufferBytes) + " bytes)");
      continue;
    }
    const unsigned char* data = model.buffers[static_cast<size_t>(view.buffer)].data.data() + view.byteOffset;
    decodeImageBytes(image, index, {data, view.byteLength}, warnings);
  }
}

/// File-system callbacks for in-memory input: every external file is missing.
bool noFileExists(const std::string&, void*) { return false; }
std::string noExpand(const std::string& path, void*) { return path; }
bool noRead(std::vector<unsigned char>*, std::string* err, const std::string& path, void*) {
  if (err) *err += "external file \"" + path + "\" is not available to in-memory input\n";
  return false;
}
bool noWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is not supported\n";
  return false;
}

}  // namespace

tinygltf::Model readModel(const std::filesystem::path& path, bool decodeImages,
                          std::vector<std::string>& warnings) {
  const std::vector<unsigned char> bytes = readFileBytes(path);
  std::filesystem::path baseDir = path.parent_path();
  if (baseDir.empty()) baseDir = ".";
  return readModel(bytes, path.string(), baseDir, decodeImages, warnings);
}

tinygltf::Model readModel(std::span<const unsigned char> bytes, const std::string& name,
                          const std::filesystem::path& baseDirPath, bool decodeImages,
                          std::vector<std::string>& warnings) {
  if (bytes.size() > kMaxFileBytes) throw std::runtime_error(name + ": file too large");
  const bool isBinary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (isBinary) validateGlbContainer(bytes, name);

  tinygltf::TinyGLTF parser;
  ImageDecodeContext context{decodeImages, &warnings, {}};
  parser.SetImageLoader(&decodeImage, &context);
  if (baseDirPath.empty()) parser.SetFsCallbacks({&noFileExists, &noExpand, &noRead, &noWrite, nullptr});
  tinygltf::Model model;
  std::string error;
  std::string warning;
  const std::string baseDir = baseDirPath.string();
  bool ok = false;
  try {
    ok = isBinary ? parser.LoadBinaryFromMemory(&model, &error, &warning, bytes.data(),
                                                static_cast<unsigned int>(bytes.size()), baseDir)
                  : parser.LoadASCIIFromString(&model, &error, &warning, reinterpret_cast<const char*>(bytes.data()),
                                               static_cast<unsigned int>(bytes.size()), baseDir);
  } catch (const std::exception& e) {
    throw std::runtime_error(name + ": glTF parse error: " + e.what());
  }
  if (!ok) {
    while (!error.empty() && (error.back() == '\n' || error.back() == '\r')) error.pop_back();
    throw std::runtime_error(name + ": glTF parse error: " + (error.empty() ? "unknown error" : error));
  }
  decodeBufferViewImages(model, context.inBufferViews, warnings);
  // tinygltf joins its warnings with newlines: one entry per line.
  size_t start = 0;
  while (start < warning.size()) {
    const size_t end = std::min(warning.find('\n', start), warning.size());
    if (end > start) warnings.push_back(warning.substr(start, end - start));
    start = end + 1;
  }
  return model;
}

}  // namespace pa::gltf::detail
