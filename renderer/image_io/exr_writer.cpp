#include "renderer/image_io/exr_writer.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include <tinyexr.h>

namespace pa::image_io {

std::vector<uint8_t> encodeExr(uint32_t width, uint32_t height, std::vector<ExrChannel> channels) {
  const size_t pixels = size_t{width} * height;
  if (pixels == 0 || channels.empty()) throw std::runtime_error("EXR: no pixels or no channels");
  for (const ExrChannel& channel : channels)
    if (channel.values.size() != pixels) throw std::runtime_error("EXR: channel " + channel.name + " has the wrong size");
  std::sort(channels.begin(), channels.end(), [](const ExrChannel& a, const ExrChannel& b) { return a.name < b.name; });

  std::vector<EXRChannelInfo> infos(channels.size());
  std::vector<int> pixelTypes(channels.size(), TINYEXR_PIXELTYPE_FLOAT);
  std::vector<unsigned char*> planes(channels.size());
  for (size_t c = 0; c < channels.size(); ++c) {
    std::memset(&infos[c], 0, sizeof(EXRChannelInfo));
    std::strncpy(infos[c].name, channels[c].name.c_str(), sizeof(infos[c].name) - 1);
    // tinyexr reads the planes only; its API takes them as non-const.
    planes[c] = const_cast<unsigned char*>(reinterpret_cast<const unsigned char*>(channels[c].values.data()));
  }
  EXRHeader header;
  InitEXRHeader(&header);
  header.num_channels = static_cast<int>(channels.size());
  header.channels = infos.data();
  header.pixel_types = pixelTypes.data();
  header.requested_pixel_types = pixelTypes.data();
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
  EXRImage image;
  InitEXRImage(&image);
  image.num_channels = static_cast<int>(channels.size());
  image.images = planes.data();
  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);

  unsigned char* memory = nullptr;
  const char* error = nullptr;
  const size_t size = SaveEXRImageToMemory(&image, &header, &memory, &error);
  if (size == 0 || memory == nullptr) {
    const std::string message = error ? error : "unknown error";
    if (error) FreeEXRErrorMessage(error);
    std::free(memory);
    throw std::runtime_error("EXR: " + message);
  }
  std::vector<uint8_t> bytes(memory, memory + size);
  std::free(memory);
  return bytes;
}

}  // namespace pa::image_io
