#pragma once
// Test and fuzz-seed helper: writes small, valid MD3 files from a description.
#include <array>
#include <cstddef>
#include <cstdint>
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

namespace q3::test {

struct Md3BuildSurface {
  std::string name = "s";
  std::vector<std::string> shaders{"models/test/skin.tga"};
  std::vector<std::array<int32_t, 3>> triangles{{0, 1, 2}};
  std::vector<std::array<float, 2>> st{{0, 0}, {1, 0}, {0, 1}};
  /// per frame, per vertex: x y z in shorts (1/64 units) and the packed normal
  std::vector<std::vector<std::array<int16_t, 4>>> frames{{{0, 0, 0, 0}, {64, 0, 0, 0}, {0, 64, 0, 0}}};
};

struct Md3BuildTag {
  std::string name;
  std::vector<std::array<float, 12>> perFrame;  ///< origin xyz, then axis[0..2]
};

class Md3Builder {
 public:
  std::vector<Md3BuildSurface> surfaces{Md3BuildSurface{}};
  std::vector<Md3BuildTag> tags;
  int numFrames = 1;

  std::vector<std::byte> build() {
    std::vector<std::byte> out(108);
    const size_t ofsFrames = out.size();
    for (int f = 0; f < numFrames; ++f) {
      for (int i = 0; i < 6; ++i) f32(float(i < 3 ? -1 : 1));  // bounds
      for (int i = 0; i < 3; ++i) f32(0);                      // origin
      f32(2.0f);                                                // radius
      str("frame" + std::to_string(f), 16);
    }
    const size_t ofsTags = out_.size() + out.size();
    for (int f = 0; f < numFrames; ++f)
      for (const auto& t : tags) {
        str(t.name, 64);
        for (float v : t.perFrame[static_cast<size_t>(f)]) f32(v);
      }
    const size_t ofsSurfaces = out_.size() + out.size();
    for (const auto& s : surfaces) surface(s);
    out.insert(out.end(), out_.begin(), out_.end());
    out_.clear();
    // header
    std::memcpy(out.data(), "IDP3", 4);
    put32(out, 4, 15);
    std::memcpy(out.data() + 8, "test.md3", 8);
    put32(out, 76, numFrames);
    put32(out, 80, static_cast<int32_t>(tags.size()));
    put32(out, 84, static_cast<int32_t>(surfaces.size()));
    put32(out, 92, static_cast<int32_t>(ofsFrames));
    put32(out, 96, static_cast<int32_t>(ofsTags));
    put32(out, 100, static_cast<int32_t>(ofsSurfaces));
    put32(out, 104, static_cast<int32_t>(out.size()));
    return out;
  }

  static void put32(std::vector<std::byte>& b, size_t at, int32_t v) { std::memcpy(b.data() + at, &v, 4); }

 private:
  void f32(float v) { raw(&v, 4); }
  void i32(int32_t v) { raw(&v, 4); }
  void raw(const void* p, size_t n) {
    auto* b = static_cast<const std::byte*>(p);
    out_.insert(out_.end(), b, b + n);
  }
  void str(const std::string& s, size_t capacity) {
    std::vector<std::byte> field(capacity, std::byte{0});
    std::memcpy(field.data(), s.data(), std::min(s.size(), capacity - 1));
    out_.insert(out_.end(), field.begin(), field.end());
  }
  void surface(const Md3BuildSurface& s) {
    const int32_t numVerts = static_cast<int32_t>(s.st.size());
    const int32_t ofsShaders = 108;
    const int32_t ofsTriangles = ofsShaders + 68 * static_cast<int32_t>(s.shaders.size());
    const int32_t ofsSt = ofsTriangles + 12 * static_cast<int32_t>(s.triangles.size());
    const int32_t ofsXyz = ofsSt + 8 * numVerts;
    const int32_t ofsEnd = ofsXyz + 8 * numVerts * static_cast<int32_t>(s.frames.size());
    raw("IDP3", 4);
    str(s.name, 64);
    for (int32_t v : {0, static_cast<int32_t>(s.frames.size()), static_cast<int32_t>(s.shaders.size()), numVerts,
                      static_cast<int32_t>(s.triangles.size()), ofsTriangles, ofsShaders, ofsSt, ofsXyz, ofsEnd})
      i32(v);
    for (size_t i = 0; i < s.shaders.size(); ++i) {
      str(s.shaders[i], 64);
      i32(static_cast<int32_t>(i));
    }
    for (const auto& t : s.triangles)
      for (int32_t v : t) i32(v);
    for (const auto& st : s.st) f32(st[0]), f32(st[1]);
    for (const auto& frame : s.frames)
      for (const auto& v : frame)
        for (int16_t c : v) raw(&c, 2);
  }
  std::vector<std::byte> out_;
};

}  // namespace q3::test
