#include "port/q3formats/shader/shader_library.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace {

using namespace q3;

TEST(ShaderLibrary, FirstDefinitionWinsAndLookupIgnoresCaseAndExtension) {
  ShaderLibrary lib;
  EXPECT_TRUE(lib.addScript("textures/a/wall { surfaceparm trans }", "one.shader"));
  EXPECT_TRUE(lib.addScript("Textures/A/Wall { surfaceparm sky }\nother { }", "two.shader"));
  EXPECT_EQ(lib.size(), 2u);
  EXPECT_EQ(lib.shadowedDefinitions(), 1u);
  const ShaderDef* wall = lib.find("TEXTURES/a/WALL.tga");
  ASSERT_NE(wall, nullptr);
  EXPECT_EQ(wall->file, "one.shader");
  EXPECT_TRUE(wall->has(SurfaceParm::Trans));
  EXPECT_NE(lib.find("textures\\a\\wall"), nullptr);
  EXPECT_EQ(lib.find("missing"), nullptr);
}

TEST(ShaderLibrary, MalformedScriptIsIgnoredWhole) {
  ShaderLibrary lib;
  EXPECT_FALSE(lib.addScript("fine { }\nbroken { { map x.tga }", "bad.shader"));
  EXPECT_EQ(lib.size(), 0u);
  ASSERT_EQ(lib.errors().size(), 1u);
  EXPECT_NE(lib.errors()[0].find("bad.shader"), std::string::npos);
}

TEST(ShaderLibrary, ScriptOrderMakesTheAlphabeticallyLastScriptWin) {
  auto order = scriptsInPriorityOrder({"scripts/b.shader", "scripts/A.shader", "scripts/c.shader"});
  EXPECT_EQ(order, (std::vector<std::string>{"scripts/c.shader", "scripts/b.shader", "scripts/A.shader"}));
}

TEST(ShaderLibrary, ImplicitShaderFromTheFirstExistingImage) {
  ShaderLibrary lib;
  std::set<std::string> files{"textures/x/plain.jpg", "textures/x/plain.png"};
  auto exists = [&](const std::string& f) { return files.contains(f); };
  auto def = lib.resolve("textures/x/plain", ImplicitLighting::Lightmap, exists);
  ASSERT_TRUE(def);
  EXPECT_TRUE(def->implicit);
  ASSERT_EQ(def->stages.size(), 2u);
  EXPECT_EQ(def->stages[0].source, TextureSource::Lightmap);
  EXPECT_EQ(def->stages[1].textures[0], "textures/x/plain.jpg");  // .tga missing, .jpg before .png
  auto model = lib.resolve("textures/x/plain.tga", ImplicitLighting::Diffuse, exists);
  ASSERT_TRUE(model);
  ASSERT_EQ(model->stages.size(), 1u);
  EXPECT_EQ(model->stages[0].rgbGen, RgbGen::LightingDiffuse);
  EXPECT_FALSE(lib.resolve("textures/x/none", ImplicitLighting::Vertex, exists));
  EXPECT_EQ(imageCandidates("a/b.jpg"),
            (std::vector<std::string>{"a/b.jpg", "a/b.tga", "a/b.jpeg", "a/b.png", "a/b.bmp"}));
  EXPECT_EQ(shaderKey("Models\\Players\\Sarge.TGA"), "models/players/sarge");
  EXPECT_EQ(shaderKey("dir.v2/name"), "dir.v2/name");
}

}  // namespace

namespace {
TEST(ShaderLibrary, AddScriptsInEngineOrderLetsTheLastScriptWin) {
  std::map<std::string, std::string> files{{"scripts/a.shader", "x { surfaceparm trans }"},
                                           {"scripts/b.shader", "x { surfaceparm sky }"},
                                           {"scripts/gone.shader", ""}};
  q3::ShaderLibrary lib;
  auto read = [&](const std::string& f) -> std::optional<std::vector<std::byte>> {
    if (f == "scripts/gone.shader") return std::nullopt;
    const std::string& t = files.at(f);
    auto* p = reinterpret_cast<const std::byte*>(t.data());
    return std::vector<std::byte>(p, p + t.size());
  };
  EXPECT_EQ(lib.addScriptsInEngineOrder({"scripts/a.shader", "scripts/b.shader", "scripts/gone.shader"}, read), 2u);
  ASSERT_NE(lib.find("x"), nullptr);
  EXPECT_EQ(lib.find("x")->file, "scripts/b.shader");
  EXPECT_TRUE(lib.find("x")->has(q3::SurfaceParm::Sky));
}
}  // namespace
