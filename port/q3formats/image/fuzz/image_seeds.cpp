// Writes the image fuzzer's seed corpus: hand-encoded TGAs of every kind the game uses and
// tiny PNG/JPG/BMP files made with stb_image_write (never copied from game data).
#include <stb_image_write.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

std::filesystem::path dir;

void write(const std::string& name, const std::vector<uint8_t>& bytes) {
  std::ofstream(dir / name, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

std::vector<uint8_t> tga(uint8_t type, uint16_t w, uint16_t h, uint8_t bpp, uint8_t desc, std::vector<uint8_t> body,
                         uint8_t mapType = 0, uint16_t mapLen = 0, uint8_t mapBits = 0) {
  std::vector<uint8_t> b = {0, mapType, type, 0, 0, uint8_t(mapLen & 0xFF), uint8_t(mapLen >> 8), mapBits, 0, 0, 0, 0,
                            uint8_t(w & 0xFF), uint8_t(w >> 8), uint8_t(h & 0xFF), uint8_t(h >> 8), bpp, desc};
  b.insert(b.end(), body.begin(), body.end());
  return b;
}

void append(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  out->insert(out->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  dir = argv[1];
  std::filesystem::create_directories(dir);
  write("rgb24_bottomup.tga", tga(2, 2, 2, 24, 0, {0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255}));
  write("rgba32_topdown.tga", tga(2, 2, 1, 32, 0x28, {1, 2, 3, 4, 5, 6, 7, 8}));
  write("rle24.tga", tga(10, 3, 2, 24, 0, {0x82, 0, 0, 255, 0x01, 255, 0, 0, 0, 255, 0, 0x80, 9, 8, 7}));
  write("rle32.tga", tga(10, 2, 2, 32, 0x28, {0x82, 10, 20, 30, 128, 0x00, 1, 2, 3, 4}));
  write("grey.tga", tga(3, 2, 1, 8, 0, {0, 200}));
  write("grey_rle.tga", tga(11, 3, 1, 8, 0, {0x82, 77}));
  write("rgb16.tga", tga(2, 1, 1, 16, 0, {0x0F, 0x7C}));
  write("mapped.tga", tga(1, 2, 1, 8, 0x20, {0, 0, 255, 255, 0, 0, 1, 0}, 1, 2, 24));

  const uint8_t px[4 * 4 * 4] = {255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 0, 255, 255, 255, 255,
                                 10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120, 130, 140, 150, 160};
  std::vector<uint8_t> png, jpg, bmp;
  stbi_write_png_to_func(append, &png, 4, 2, 4, px, 16);
  stbi_write_jpg_to_func(append, &jpg, 4, 2, 4, px, 90);
  stbi_write_bmp_to_func(append, &bmp, 4, 2, 4, px);
  write("rgba.png", png);
  write("rgb.jpg", jpg);
  write("rgba.bmp", bmp);
  return 0;
}
