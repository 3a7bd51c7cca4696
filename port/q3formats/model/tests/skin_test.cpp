#include "port/q3formats/model/skin.h"

#include <gtest/gtest.h>

namespace {

TEST(Skin, ParsesPairsSkipsTagsAndToleratesFormatting) {
  const char* text =
      "tag_head,\r\n"
      "h_Head,models/players/sarge/head.tga\r\n"
      "  u_torso , \"models/players/sarge/torso blue.tga\"  \n"
      "// a comment line\n"
      "l_legs,models/players/sarge/legs.tga // trailing comment\n"
      "tag_weapon,\n"
      "h_visor,\n"
      "\n";
  q3::Skin skin = q3::parseSkin(text, "head_default.skin");
  ASSERT_EQ(skin.surfaces.size(), 3u);
  EXPECT_EQ(skin.surfaces[0].surface, "h_head");
  EXPECT_EQ(skin.surfaces[0].shader, "models/players/sarge/head.tga");
  EXPECT_EQ(skin.surfaces[1].surface, "u_torso");
  EXPECT_EQ(skin.surfaces[1].shader, "models/players/sarge/torso blue.tga");
  EXPECT_EQ(skin.surfaces[2].shader, "models/players/sarge/legs.tga");
  ASSERT_EQ(skin.warnings.size(), 1u);  // h_visor has no shader
  EXPECT_NE(skin.warnings[0].find("head_default.skin:7"), std::string::npos) << skin.warnings[0];
  EXPECT_EQ(skin.shaderFor("H_HEAD"), "models/players/sarge/head.tga");
  EXPECT_EQ(skin.shaderFor("missing"), "");
}

TEST(Skin, EmptyAndGarbageInputsAreHarmless) {
  EXPECT_TRUE(q3::parseSkin("", "e.skin").surfaces.empty());
  EXPECT_TRUE(q3::parseSkin(",,,,\n,\n", "c.skin").surfaces.empty());
  std::string binary(300, '\0');
  binary[10] = '\xff';
  EXPECT_TRUE(q3::parseSkin(binary, "b.skin").surfaces.size() <= 1);
}

TEST(Skin, CapsTheNumberOfSurfaces) {
  std::string text;
  for (int i = 0; i < 300; ++i) {
    text += std::to_string(i);  // (not "s" + to_string: GCC 12 -Wrestrict false positive)
    text += ",x.tga\n";
  }
  q3::Skin skin = q3::parseSkin(text, "many.skin");
  EXPECT_EQ(skin.surfaces.size(), q3::kMaxSkinSurfaces);
  EXPECT_FALSE(skin.warnings.empty());
}

}  // namespace
