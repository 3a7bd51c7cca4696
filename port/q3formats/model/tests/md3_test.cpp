#include "port/q3formats/model/md3.h"

#include <gtest/gtest.h>

#include <cmath>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/model/tests/md3_builder.h"

namespace {

using q3::test::Md3Builder;

Md3Builder twoFrameModel() {
  Md3Builder b;
  b.numFrames = 2;
  auto& s = b.surfaces[0];
  s.name = "h_head";
  s.shaders = {"models/players/a/head.tga", "models/players/a/head_red.tga"};
  // frame 0: triangle at z = 0; frame 1: moved up by 2 units (128 / 64), normals tilted.
  s.frames = {{{0, 0, 0, 0}, {64, 0, 0, 0}, {0, 64, 0, 0}},
              {{0, 0, 128, 64}, {64, 0, 128, 64}, {0, 64, 128, 64}}};
  b.tags = {{"tag_weapon", {{1, 2, 3, 1, 0, 0, 0, 1, 0, 0, 0, 1}, {3, 2, 1, 0, 1, 0, -1, 0, 0, 0, 0, 1}}}};
  return b;
}

TEST(Md3, ParsesHeaderFramesTagsAndSurfaces) {
  auto bytes = twoFrameModel().build();
  q3::Md3Model m = q3::parseMd3(bytes, "head.md3");
  EXPECT_EQ(m.name, "test.md3");
  ASSERT_EQ(m.frames.size(), 2u);
  EXPECT_EQ(m.frames[1].name, "frame1");
  EXPECT_FLOAT_EQ(m.frames[0].mins[0], -1);
  EXPECT_FLOAT_EQ(m.frames[0].radius, 2);
  ASSERT_EQ(m.numTags, 1);
  EXPECT_EQ(m.tag(1, 0).name, "tag_weapon");
  EXPECT_FLOAT_EQ(m.tag(1, 0).origin[0], 3);
  ASSERT_EQ(m.surfaces.size(), 1u);
  const auto& s = m.surfaces[0];
  EXPECT_EQ(s.name, "h_head");
  ASSERT_EQ(s.shaders.size(), 2u);
  EXPECT_EQ(s.shaders[1].name, "models/players/a/head_red.tga");
  EXPECT_EQ(s.numVerts, 3);
  EXPECT_EQ(s.triangles[0], (std::array<uint32_t, 3>{0, 1, 2}));
  EXPECT_FLOAT_EQ(s.texCoords[1][0], 1);
  EXPECT_FLOAT_EQ(s.positions[1][0], 1.0f);  // 64 / 64
  EXPECT_FLOAT_EQ(s.positions[3 + 2][2], 2.0f);
  // packed 0: lat 0, lng 0 -> (0, 0, 1)
  EXPECT_NEAR(s.normals[0][2], 1.0f, 1e-6);
}

TEST(Md3, NormalDecodingKnownAnswers) {
  auto up = q3::decodeMd3Normal(0x0000);
  EXPECT_NEAR(up[2], 1, 1e-6);
  auto x = q3::decodeMd3Normal(0x0040);  // lat 0, lng 64 (90 degrees) -> +X
  EXPECT_NEAR(x[0], 1, 1e-6);
  EXPECT_NEAR(x[2], 0, 1e-6);
  auto y = q3::decodeMd3Normal(0x4040);  // lat 90, lng 90 -> +Y
  EXPECT_NEAR(y[1], 1, 1e-6);
  auto down = q3::decodeMd3Normal(0x0080);  // lng 180 -> -Z
  EXPECT_NEAR(down[2], -1, 1e-6);
}

TEST(Md3, LerpBetweenFrames) {
  auto bytes = twoFrameModel().build();
  q3::Md3Model m = q3::parseMd3(bytes, "head.md3");
  std::vector<q3::Md3Vec3> pos, nrm;
  q3::lerpSurface(m.surfaces[0], m.frames.size(), 1, 0, 0.25f, pos, nrm);  // 75% frame 1
  ASSERT_EQ(pos.size(), 3u);
  EXPECT_NEAR(pos[0][2], 1.5f, 1e-6);
  const float len = std::sqrt(nrm[0][0] * nrm[0][0] + nrm[0][1] * nrm[0][1] + nrm[0][2] * nrm[0][2]);
  EXPECT_NEAR(len, 1.0f, 1e-5);
  q3::lerpSurface(m.surfaces[0], m.frames.size(), 99, -5, 0.5f, pos, nrm);  // out of range -> frame 0
  EXPECT_NEAR(pos[0][2], 0.0f, 1e-6);
}

TEST(Md3, LerpTagKnownAnswer) {
  auto bytes = twoFrameModel().build();
  q3::Md3Model m = q3::parseMd3(bytes, "head.md3");
  auto tag = q3::lerpTag(m, 0, 1, 0.5f, "tag_weapon");
  ASSERT_TRUE(tag);
  EXPECT_NEAR(tag->origin[0], 2, 1e-6);
  EXPECT_NEAR(tag->origin[2], 2, 1e-6);
  // axis[0] halfway between +X and +Y, renormalised.
  EXPECT_NEAR(tag->axis[0][0], std::sqrt(0.5f), 1e-6);
  EXPECT_NEAR(tag->axis[0][1], std::sqrt(0.5f), 1e-6);
  EXPECT_FALSE(q3::lerpTag(m, 0, 1, 0.5f, "tag_missing"));
  EXPECT_FALSE(q3::lerpTag(m, 0, 1, 0.5f, "TAG_WEAPON"));  // strcmp, like the engine
  auto clamped = q3::lerpTag(m, 7, 9, 0.0f, "tag_weapon");    // frames clamp to the last
  ASSERT_TRUE(clamped);
  EXPECT_NEAR(clamped->origin[0], 3, 1e-6);
}

TEST(Md3, LodNames) {
  EXPECT_EQ(q3::md3LodName("models/players/sarge/head.md3", 0), "models/players/sarge/head.md3");
  EXPECT_EQ(q3::md3LodName("models/players/sarge/head.md3", 1), "models/players/sarge/head_1.md3");
  EXPECT_EQ(q3::md3LodName("models/x.MD3", 2), "models/x_2.md3");
}

void expectRejected(std::vector<std::byte> bytes, const std::string& field) {
  try {
    q3::parseMd3(bytes, "bad.md3");
    FAIL() << "accepted; expected a complaint about " << field;
  } catch (const q3::FormatError& e) {
    EXPECT_EQ(e.file().substr(0, 7), "bad.md3");
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(Md3, MalformedInputsAreRejectedWithTheField) {
  auto good = twoFrameModel().build();
  expectRejected({}, "header");
  auto b = good;
  b[0] = std::byte{'X'};
  expectRejected(b, "ident");
  b = good;
  Md3Builder::put32(b, 4, 16);
  expectRejected(b, "version");
  b = good;
  Md3Builder::put32(b, 76, 5000);
  expectRejected(b, "numFrames");
  b = good;
  Md3Builder::put32(b, 76, 0);
  expectRejected(b, "numFrames");
  b = good;
  Md3Builder::put32(b, 84, -1);
  expectRejected(b, "numSurfaces");
  b = good;
  Md3Builder::put32(b, 96, 0x7FFFFFF0);
  expectRejected(b, "tags");
  b = good;
  Md3Builder::put32(b, 100, static_cast<int32_t>(b.size()) - 4);
  expectRejected(b, "surface 0");
  b = good;
  b.resize(b.size() - 10);
  expectRejected(b, "ofsEnd");

  // A triangle index beyond numVerts.
  Md3Builder badIndex = twoFrameModel();
  badIndex.surfaces[0].triangles = {{0, 1, 3}};
  expectRejected(badIndex.build(), "triangles");
  // Surface frame count that disagrees with the model.
  Md3Builder frames = twoFrameModel();
  frames.numFrames = 1;
  frames.tags[0].perFrame.resize(1);
  expectRejected(frames.build(), "numFrames");
}

TEST(Md3, TruncationAtEveryLengthNeverCrashes) {
  auto good = twoFrameModel().build();
  for (size_t n = 0; n < good.size(); ++n) {
    std::vector<std::byte> cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(n));
    EXPECT_THROW(q3::parseMd3(cut, "cut.md3"), q3::FormatError) << n;
  }
}

}  // namespace
