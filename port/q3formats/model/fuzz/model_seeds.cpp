// Writes seed corpora for the MD3 and skin fuzzers (generated, never copied from game data).
#include <filesystem>
#include <fstream>
#include <string>

#include "port/q3formats/model/tests/md3_builder.h"

namespace {
void write(const std::filesystem::path& file, const std::vector<std::byte>& bytes) {
  std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) return 2;  // md3_dir skin_dir
  const std::filesystem::path md3Dir = argv[1], skinDir = argv[2];
  std::filesystem::create_directories(md3Dir);
  std::filesystem::create_directories(skinDir);

  q3::test::Md3Builder single;
  write(md3Dir / "single.md3", single.build());

  q3::test::Md3Builder animated;
  animated.numFrames = 2;
  animated.surfaces[0].frames = {{{0, 0, 0, 0}, {64, 0, 0, 0x40}, {0, 64, 0, 0x4040}},
                                 {{0, 0, 128, 0x80}, {64, 0, 128, 0x20}, {0, 64, 128, 0x1010}}};
  animated.tags = {{"tag_weapon", {{1, 2, 3, 1, 0, 0, 0, 1, 0, 0, 0, 1}, {3, 2, 1, 0, 1, 0, -1, 0, 0, 0, 0, 1}}},
                   {"tag_head", {{0, 0, 9, 1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 8, 1, 0, 0, 0, 1, 0, 0, 0, 1}}}};
  q3::test::Md3BuildSurface second;
  second.name = "u_torso";
  second.shaders = {"a.tga", "b.tga"};
  second.st = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  second.triangles = {{0, 1, 2}, {1, 3, 2}};
  second.frames = {{{0, 0, 0, 0}, {64, 0, 0, 0}, {0, 64, 0, 0}, {64, 64, 0, 0}},
                   {{0, 0, 64, 0}, {64, 0, 64, 0}, {0, 64, 64, 0}, {64, 64, 64, 0}}};
  animated.surfaces.push_back(second);
  write(md3Dir / "animated.md3", animated.build());

  std::ofstream(skinDir / "head.skin", std::ios::binary)
      << "tag_head,\r\nh_head,models/players/x/head.tga\r\nh_visor,\"models/players/x/visor 2.tga\"\n";
  std::ofstream(skinDir / "upper.skin", std::ios::binary)
      << "// comment\nu_torso , models/players/x/torso.tga\ntag_weapon,\nu_arm,x.tga extra\n,,\n";
  return 0;
}
