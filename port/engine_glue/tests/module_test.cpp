// Drives the built renderer module through GetRefAPI, exactly as the engine does (dlopen,
// refimport_t, refexport_t), with the fake engine. Needs an X display (run under xvfb-run).
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <stb_image.h>
#include <stb_image_write.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>

#include "fake_engine.h"
#include "port/q3formats/bsp/tests/external_lightmap_map.h"
#include "port/q3formats/model/tests/md3_builder.h"
#include "port/q3formats/vfs/game_filesystem.h"

namespace {

using q3abi::refexport_t;

void appendBytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  out->insert(out->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
}

/// A solid-colour TGA file.
std::vector<uint8_t> solidTga(int w, int h, uint8_t r, uint8_t g, uint8_t b, uint8_t a) {
  std::vector<uint8_t> pixels;
  for (int i = 0; i < w * h; ++i) pixels.insert(pixels.end(), {r, g, b, a});
  std::vector<uint8_t> file;
  stbi_write_tga_to_func(appendBytes, &file, w, h, 4, pixels.data());
  return file;
}

/// A tiny MD3: two frames, one tag "tag_weapon" moving from origin (0,0,0) to (10,20,30).
std::vector<uint8_t> tinyMd3() {
  constexpr int kHeader = 108, kFrame = 56, kTag = 112;
  std::vector<uint8_t> bytes(kHeader + 2 * kFrame + 2 * kTag, 0);
  auto put32 = [&](size_t at, int32_t v) { std::memcpy(&bytes[at], &v, 4); };
  auto putF = [&](size_t at, float v) { std::memcpy(&bytes[at], &v, 4); };
  std::memcpy(&bytes[0], "IDP3", 4);
  put32(4, 15);
  put32(76, 2);   // frames
  put32(80, 1);   // tags
  put32(84, 0);   // surfaces
  put32(92, kHeader);
  put32(96, kHeader + 2 * kFrame);
  put32(100, kHeader + 2 * kFrame + 2 * kTag);
  put32(104, kHeader + 2 * kFrame + 2 * kTag);
  for (int f = 0; f < 2; ++f) {
    const size_t at = kHeader + f * kFrame;
    for (int k = 0; k < 3; ++k) {
      putF(at + 4 * k, -8.0f - f);
      putF(at + 12 + 4 * k, 8.0f + f);
    }
    const size_t tag = kHeader + 2 * kFrame + f * kTag;
    std::memcpy(&bytes[tag], "tag_weapon", 10);
    putF(tag + 64, 10.0f * f);
    putF(tag + 68, 20.0f * f);
    putF(tag + 72, 30.0f * f);
    putF(tag + 76, 1.0f);   // axis = identity
    putF(tag + 92, 1.0f);
    putF(tag + 108, 1.0f);
  }
  return bytes;
}

/// Unmounts the game data before static destruction (physfs' registry is a static too).
class UnmountGameData : public ::testing::Environment {
 public:
  void TearDown() override { fake::engine().game.reset(); }
};
const auto* const kUnmount = ::testing::AddGlobalTestEnvironment(new UnmountGameData);

class ModuleTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fake::reset();
    library_ = dlopen(GLUE_MODULE_PATH, RTLD_NOW | RTLD_LOCAL);
    ASSERT_NE(library_, nullptr) << dlerror();
    getRefApi_ = reinterpret_cast<GetRefApi>(dlsym(library_, "GetRefAPI"));
    ASSERT_NE(getRefApi_, nullptr);
    imports_ = fake::imports();
    re_ = getRefApi_(q3abi::kRefApiVersion, &imports_);
    ASSERT_NE(re_, nullptr);
    fake::engine().setCvar("r_mode", "3");   // 640x480
    fake::engine().setCvar("r_fullscreen", "0");
  }

  void TearDown() override {
    if (re_ != nullptr) re_->Shutdown(1);
    if (library_ != nullptr) dlclose(library_);
  }

  void begin() {
    std::memset(&config_, 0, sizeof config_);
    re_->BeginRegistration(&config_);
  }

  /// Renders one frame with `draw`, takes a PNG screenshot, returns its RGB pixels.
  template <typename Draw>
  std::vector<uint8_t> frameToPixels(Draw&& draw, int& width, int& height) {
    re_->BeginFrame(q3abi::STEREO_CENTER);
    draw();
    EXPECT_TRUE(fake::engine().runCommand({"screenshotPNG", "unit"}));
    re_->EndFrame(nullptr, nullptr);
    const auto found = fake::engine().written.find("screenshots/unit.png");
    if (found == fake::engine().written.end()) return {};
    int channels = 0;
    stbi_uc* pixels = stbi_load_from_memory(found->second.data(), int(found->second.size()),
                                            &width, &height, &channels, 3);
    std::vector<uint8_t> out(pixels, pixels + width * height * 3);
    stbi_image_free(pixels);
    fake::engine().written.clear();
    return out;
  }

  /// A HUD model view (RDF_NOWORLDMODEL) of size x size at (x, y), looking down +x.
  static q3abi::refdef_t modelView(int size, int x = 0, int y = 0) {
    q3abi::refdef_t view{};
    view.x = x;
    view.y = y;
    view.width = view.height = size;
    view.fov_x = view.fov_y = 30.0f;
    view.viewaxis[0][0] = view.viewaxis[1][1] = view.viewaxis[2][2] = 1.0f;
    view.rdflags = q3abi::RDF_NOWORLDMODEL;
    return view;
  }

  using GetRefApi = refexport_t* (*)(int, q3abi::refimport_t*);
  void* library_ = nullptr;
  GetRefApi getRefApi_ = nullptr;
  q3abi::refimport_t imports_{};
  refexport_t* re_ = nullptr;
  q3abi::glconfig_t config_{};
};

TEST(GetRefApi, RefusesOtherApiVersions) {
  void* library = dlopen(GLUE_MODULE_PATH, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(library, nullptr) << dlerror();
  auto get = reinterpret_cast<refexport_t* (*)(int, q3abi::refimport_t*)>(dlsym(library, "GetRefAPI"));
  q3abi::refimport_t ri = fake::imports();
  EXPECT_EQ(get(7, &ri), nullptr);
  EXPECT_TRUE(fake::engine().printed("mismatched refresh API version 7"));
  refexport_t* re = get(8, &ri);
  ASSERT_NE(re, nullptr);
  // Every one of the 30 entry points is filled.
  auto* slots = reinterpret_cast<void**>(re);
  for (size_t i = 0; i < sizeof(refexport_t) / sizeof(void*); ++i) EXPECT_NE(slots[i], nullptr) << i;
  re->Shutdown(1);
  dlclose(library);
}

TEST_F(ModuleTest, BeginRegistrationOpensTheWindowAndDescribesIt) {
  begin();
  EXPECT_TRUE(fake::engine().printed("PathArena path tracer renderer"));
  EXPECT_EQ(config_.vidWidth, 640);
  EXPECT_EQ(config_.vidHeight, 480);
  EXPECT_FLOAT_EQ(config_.windowAspect, 640.0f / 480.0f);
  EXPECT_GT(std::strlen(config_.renderer_string), 0u);
  EXPECT_GT(std::strlen(config_.version_string), 0u);
  EXPECT_GE(config_.maxTextureSize, 1024);
  EXPECT_EQ(config_.colorBits, 24);
  EXPECT_EQ(config_.isFullscreen, 0);
  EXPECT_EQ(fake::engine().inInit, 1);
  EXPECT_TRUE(fake::engine().commands.count("screenshotPNG"));
  EXPECT_TRUE(fake::engine().cvars.count("r_pt_preset"));
  EXPECT_TRUE(fake::engine().cvars.count("r_pt_spp"));
  // Russian roulette from the first bounce by default (docs/performance.md, "Russian roulette").
  ASSERT_TRUE(fake::engine().cvars.count("r_pt_roulette"));
  EXPECT_EQ(fake::engine().cvars.at("r_pt_roulette")->integer, 1);
  // Lamps hidden from a region chosen less often there by default (docs/performance.md,
  // "Lamps behind walls").
  ASSERT_TRUE(fake::engine().cvars.count("r_pt_lamp_vis"));
  EXPECT_EQ(fake::engine().cvars.at("r_pt_lamp_vis")->integer, 1);
}

TEST_F(ModuleTest, RegistrationDrawsFromRandLikeTheStockRenderer) {
  // The game's random effects come from the same rand() sequence: after BeginRegistration it
  // stands where opengl1 leaves it (512 draws for its noise lattice).
  begin();
  re_->Shutdown(0);
  std::srand(5);
  re_->BeginRegistration(&config_);
  const int next = std::rand();
  std::srand(5);
  for (int i = 0; i < 512; ++i) (void)std::rand();
  EXPECT_EQ(next, std::rand());
}

TEST_F(ModuleTest, CustomModeIsHonoured) {
  fake::engine().setCvar("r_mode", "-1");
  fake::engine().setCvar("r_customwidth", "320");
  fake::engine().setCvar("r_customheight", "200");
  begin();
  EXPECT_EQ(config_.vidWidth, 320);
  EXPECT_EQ(config_.vidHeight, 200);
}

TEST_F(ModuleTest, ShutdownIsIdempotentAndRemovesCommands) {
  begin();
  re_->Shutdown(0);
  re_->Shutdown(0);   // the engine calls it twice on map change
  EXPECT_TRUE(fake::engine().commands.empty());
  begin();            // same window, no second IN_Init
  EXPECT_EQ(fake::engine().inInit, 1);
  EXPECT_EQ(config_.vidWidth, 640);
  re_->Shutdown(1);
  EXPECT_EQ(fake::engine().inShutdown, 1);
  EXPECT_TRUE(fake::engine().commands.empty());
  re_->Shutdown(1);
  EXPECT_EQ(fake::engine().inShutdown, 1);
  begin();            // vid_restart without dlclose: a fresh window
  EXPECT_EQ(fake::engine().inInit, 2);
}

TEST_F(ModuleTest, StretchPicDrawsTheImageTintedBySetColor) {
  fake::engine().files["gfx/test/red.tga"] = solidTga(8, 8, 255, 0, 0, 255);
  begin();
  const q3abi::qhandle_t red = re_->RegisterShaderNoMip("gfx/test/red");
  ASSERT_GT(red, 0);
  EXPECT_EQ(re_->RegisterShaderNoMip("gfx/test/red.tga"), red);   // extension is a hint
  EXPECT_EQ(re_->RegisterShaderNoMip("gfx/test/missing"), 0);     // default shader
  int w = 0, h = 0;
  const auto pixels = frameToPixels([&] {
    re_->SetColor(nullptr);
    re_->DrawStretchPic(0, 0, 320, 480, 0, 0, 1, 1, red);
    const float halfGreen[4] = {0.0f, 1.0f, 0.0f, 1.0f};
    re_->SetColor(halfGreen);   // implicit 2D shaders are tinted by SetColor
    re_->DrawStretchPic(320, 0, 320, 480, 0, 0, 1, 1, red);
    re_->SetColor(nullptr);
  }, w, h);
  ASSERT_EQ(w, 640);
  ASSERT_EQ(h, 480);
  const uint8_t* left = &pixels[(240 * 640 + 100) * 3];
  const uint8_t* right = &pixels[(240 * 640 + 500) * 3];
  EXPECT_EQ(left[0], 255);
  EXPECT_EQ(left[1], 0);
  EXPECT_EQ(right[0], 0);   // red * green tint = black
  EXPECT_EQ(right[1], 0);
}

TEST_F(ModuleTest, ShaderScriptBlendModesApply) {
  fake::engine().files["gfx/test/white.tga"] = solidTga(4, 4, 255, 255, 255, 255);
  fake::engine().files["gfx/test/blue.tga"] = solidTga(4, 4, 0, 0, 255, 255);
  fake::engine().files["scripts/test.shader"] = [] {
    const std::string text =
        "// additive overlay\n"
        "test/addblue\n{\n  nopicmip\n  {\n    map gfx/test/blue.tga\n    blendFunc add\n  }\n}\n"
        "test/addblue\n{\n  { map gfx/test/white.tga }\n}\n";   // second definition loses
    return std::vector<uint8_t>(text.begin(), text.end());
  }();
  fake::engine().files["gfx/test/red.tga"] = solidTga(4, 4, 255, 0, 0, 255);
  begin();
  const q3abi::qhandle_t red = re_->RegisterShaderNoMip("gfx/test/red");
  const q3abi::qhandle_t add = re_->RegisterShaderNoMip("test/addblue");
  ASSERT_GT(add, 0);
  int w = 0, h = 0;
  const auto pixels = frameToPixels([&] {
    re_->DrawStretchPic(0, 0, 640, 480, 0, 0, 1, 1, red);
    re_->DrawStretchPic(0, 0, 640, 480, 0, 0, 1, 1, add);
  }, w, h);
  ASSERT_FALSE(pixels.empty());
  const uint8_t* p = &pixels[(100 * 640 + 100) * 3];
  EXPECT_EQ(p[0], 255);   // red + blue
  EXPECT_EQ(p[1], 0);
  EXPECT_EQ(p[2], 255);
}

TEST_F(ModuleTest, FontWithoutPrerenderedFileUsesTheBitmapFont) {
  fake::engine().files["gfx/2d/bigchars.tga"] = solidTga(256, 256, 255, 255, 255, 255);
  begin();
  q3abi::fontInfo_t font{};
  re_->RegisterFont("fonts/font", 16, &font);
  const q3abi::glyphInfo_t& a = font.glyphs[int('A')];
  EXPECT_GT(a.glyph, 0);
  EXPECT_FLOAT_EQ(a.s, (65 % 16) / 16.0f);
  EXPECT_FLOAT_EQ(a.t, (65 / 16) / 16.0f);
  EXPECT_EQ(a.xSkip, 16);
  EXPECT_FLOAT_EQ(font.glyphScale, 3.0f);
  EXPECT_STREQ(font.name, "fonts/fontImage_16.dat");
}

TEST_F(ModuleTest, LerpTagAndModelBoundsFromAnMd3) {
  fake::engine().files["models/test/box.md3"] = tinyMd3();
  begin();
  const q3abi::qhandle_t model = re_->RegisterModel("models/test/box.md3");
  ASSERT_GT(model, 0);
  EXPECT_EQ(re_->RegisterModel("models/test/missing.md3"), 0);
  q3abi::orientation_t tag{};
  EXPECT_EQ(re_->LerpTag(&tag, model, 0, 1, 0.5f, "tag_weapon"), 1);
  EXPECT_FLOAT_EQ(tag.origin[0], 5.0f);
  EXPECT_FLOAT_EQ(tag.origin[1], 10.0f);
  EXPECT_FLOAT_EQ(tag.origin[2], 15.0f);
  EXPECT_FLOAT_EQ(tag.axis[0][0], 1.0f);
  EXPECT_EQ(re_->LerpTag(&tag, model, 0, 99, 1.0f, "tag_weapon"), 1);   // frame clamped
  EXPECT_FLOAT_EQ(tag.origin[2], 30.0f);
  EXPECT_EQ(re_->LerpTag(&tag, model, 0, 1, 0.5f, "tag_head"), 0);
  EXPECT_FLOAT_EQ(tag.origin[0], 0.0f);
  EXPECT_FLOAT_EQ(tag.axis[1][1], 1.0f);
  float mins[3], maxs[3];
  re_->ModelBounds(model, mins, maxs);
  EXPECT_FLOAT_EQ(mins[0], -8.0f);
  EXPECT_FLOAT_EQ(maxs[2], 8.0f);
}

TEST_F(ModuleTest, HostileCallsAreSurvived) {
  begin();
  EXPECT_EQ(re_->RegisterShader(nullptr), 0);
  EXPECT_EQ(re_->RegisterModel(std::string(200, 'x').c_str()), 0);
  EXPECT_EQ(re_->RegisterSkin("models/none.skin"), 0);
  fake::engine().files["models/bad.md3"] = {'I', 'D', 'P', '3', 0xff};
  EXPECT_EQ(re_->RegisterModel("models/bad.md3"), 0);
  re_->BeginFrame(0);
  re_->DrawStretchPic(NAN, 0, 10, 10, 0, 0, 1, 1, 12345);
  re_->DrawStretchRaw(0, 0, 10, 10, -1, 5, nullptr, 0, 1);
  re_->AddRefEntityToScene(nullptr);
  q3abi::refEntity_t bad{};
  bad.reType = 99;
  re_->AddRefEntityToScene(&bad);
  re_->AddPolyToScene(0, 3, nullptr, 1);
  const float origin[3] = {0, 0, 0};
  re_->AddLightToScene(origin, -5.0f, 1, 1, 1);
  q3abi::orientation_t tag{};
  EXPECT_EQ(re_->LerpTag(&tag, 777, 0, 0, 0, "tag"), 0);
  re_->EndFrame(nullptr, nullptr);
  char token[64];
  EXPECT_EQ(re_->GetEntityToken(token, sizeof token), 0);   // no world
}

TEST_F(ModuleTest, HudModelViewWorksWithoutAWorld) {
  begin();
  re_->BeginFrame(0);
  re_->ClearScene();
  q3abi::refEntity_t head{};
  head.reType = q3abi::RT_MODEL;
  head.axis[0][0] = head.axis[1][1] = head.axis[2][2] = 1.0f;
  re_->AddRefEntityToScene(&head);
  const q3abi::refdef_t view = modelView(48, 10, 10);
  re_->RenderScene(&view);
  re_->EndFrame(nullptr, nullptr);
  EXPECT_EQ(fake::engine().lastErrorLevel, -1);
}

/// The 48 x 48 pixels (RGB) of modelView(48, 10, 10) in a window's pixels.
std::vector<uint8_t> viewPixels(const std::vector<uint8_t>& pixels, int width, int height) {
  std::vector<uint8_t> inView;
  for (int y = 10; y < 58 && y < height; ++y)
    for (int x = 10; x < 58 && x < width; ++x)
      for (int c = 0; c < 3; ++c) inView.push_back(pixels[(size_t(y) * width + x) * 3 + c]);
  return inView;
}

/// A 32 x 32 quad model across the view of modelView (normals -z), with an orange skin, stored
/// in the fake engine's files as models/test/quad.md3.
void storeTestQuadModel() {
  q3::test::Md3Builder md3;
  q3::test::Md3BuildSurface& quad = md3.surfaces[0];
  quad.shaders = {"models/test/skin"};
  quad.st = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const int16_t facingDown = (64 << 8) | 128;   // packed normal -z (latitude byte 128: 180 degrees)
  quad.frames = {{{0, -16 * 64, -16 * 64, facingDown},
                  {0, 16 * 64, -16 * 64, facingDown},
                  {0, 16 * 64, 16 * 64, facingDown},
                  {0, -16 * 64, 16 * 64, facingDown}}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 2, 1}, {0, 3, 2}};   // both windings: seen whichever is front
  const std::vector<std::byte> bytes = md3.build();
  fake::engine().files["models/test/quad.md3"] =
      std::vector<uint8_t>(reinterpret_cast<const uint8_t*>(bytes.data()),
                           reinterpret_cast<const uint8_t*>(bytes.data()) + bytes.size());
  fake::engine().files["models/test/skin.tga"] = solidTga(8, 8, 200, 120, 40, 255);
}

/// An entity of `model` 100 units in front of modelView's camera.
q3abi::refEntity_t quadInFront(q3abi::qhandle_t model) {
  q3abi::refEntity_t icon{};
  icon.reType = q3abi::RT_MODEL;
  icon.hModel = model;
  icon.origin[0] = 100.0f;   // in front of the view, which looks down +x
  icon.axis[0][0] = icon.axis[1][1] = icon.axis[2][2] = 1.0f;
  return icon;
}

TEST_F(ModuleTest, HudModelViewsShowTheStockLookInEveryPreset) {
  // A HUD model view (an icon, the status bar's head) has no world to light it: every preset
  // draws it as the lightmap preset does, the stock entity light on its textures, the same pixels.
  storeTestQuadModel();
  begin();
  const q3abi::qhandle_t model = re_->RegisterModel("models/test/quad.md3");
  ASSERT_GT(model, 0);
  re_->EndRegistration();
  const q3abi::refEntity_t icon = quadInFront(model);
  const q3abi::refdef_t view = modelView(48, 10, 10);
  const auto picture = [&](const char* preset) {
    fake::engine().setCvar("r_pt_preset", preset);
    int width = 0, height = 0;
    std::vector<uint8_t> pixels = frameToPixels(
        [&] {
          re_->ClearScene();
          re_->AddRefEntityToScene(&icon);
          re_->RenderScene(&view);
        },
        width, height);
    return viewPixels(pixels, width, height);
  };
  const std::vector<uint8_t> stock = picture("lightmap");
  ASSERT_EQ(stock.size(), size_t{48 * 48 * 3});
  const size_t centre = (size_t{24} * 48 + 24) * 3;
  EXPECT_GT(stock[centre], 60) << "the icon is not drawn";
  for (const char* preset : {"direct", "path", "reference"}) EXPECT_EQ(picture(preset), stock) << preset;
  EXPECT_EQ(fake::engine().lastErrorLevel, -1);
}

TEST_F(ModuleTest, DynamicLightsAreLeftOutWithRDynamiclightZero) {
  // As stock: r_dynamiclight 0 drops the game's dynamic lights (explosions, shots) from the scene.
  storeTestQuadModel();
  fake::engine().files["scripts/test.shader"] = [] {
    const std::string text = "models/test/skin\n{\n  {\n    map models/test/skin.tga\n    rgbGen lightingDiffuse\n  }\n}\n";
    return std::vector<uint8_t>(text.begin(), text.end());
  }();
  begin();
  ASSERT_TRUE(fake::engine().cvars.count("r_dynamiclight"));
  EXPECT_EQ(fake::engine().cvars.at("r_dynamiclight")->integer, 1);
  const q3abi::qhandle_t model = re_->RegisterModel("models/test/quad.md3");
  ASSERT_GT(model, 0);
  re_->EndRegistration();
  const q3abi::refEntity_t icon = quadInFront(model);
  const q3abi::refdef_t view = modelView(48, 10, 10);
  const auto picture = [&](bool withLight) {
    int width = 0, height = 0;
    std::vector<uint8_t> pixels = frameToPixels(
        [&] {
          re_->ClearScene();
          re_->AddRefEntityToScene(&icon);
          const float origin[3] = {100.0f, 0.0f, -24.0f};   // on the side the quad's normals face (-z)
          if (withLight) re_->AddLightToScene(origin, 200.0f, 0.2f, 0.2f, 1.0f);
          re_->RenderScene(&view);
        },
        width, height);
    return viewPixels(pixels, width, height);
  };
  const std::vector<uint8_t> lit = picture(true);
  const std::vector<uint8_t> unlit = picture(false);
  const size_t centre = (size_t{24} * 48 + 24) * 3;
  ASSERT_EQ(lit.size(), size_t{48 * 48 * 3});
  EXPECT_GT(lit[centre + 2], unlit[centre + 2]) << "the blue dynamic light adds nothing";
  fake::engine().setCvar("r_dynamiclight", "0");
  EXPECT_EQ(picture(true), unlit);
  EXPECT_EQ(fake::engine().lastErrorLevel, -1);
}

TEST_F(ModuleTest, EndRegistrationMakesTheMaterialsBeforeTheFirstView) {
  // The stock renderer loads images as they are registered; this module makes its textures and
  // materials at EndRegistration, in the loading screen, so that the first frame of play does not.
  fake::engine().files["models/test/skin.tga"] = solidTga(8, 8, 200, 100, 50, 255);
  fake::engine().setCvar("developer", "1");
  begin();
  ASSERT_GT(re_->RegisterShader("models/test/skin"), 0);
  fake::engine().prints.clear();
  re_->EndRegistration();
  EXPECT_TRUE(fake::engine().printed("prepared shaders")) << "no materials made at EndRegistration";
  EXPECT_EQ(fake::engine().lastErrorLevel, -1);
  fake::engine().prints.clear();
  re_->BeginFrame(0);
  re_->ClearScene();
  const q3abi::refdef_t view = modelView(48);
  re_->RenderScene(&view);
  re_->EndFrame(nullptr, nullptr);
  EXPECT_FALSE(fake::engine().printed("prepared shaders")) << "the first view made materials again";
  // A shader registered during play gets its materials at the next view, as before.
  fake::engine().files["models/test/late.tga"] = solidTga(8, 8, 10, 20, 30, 255);
  ASSERT_GT(re_->RegisterShader("models/test/late"), 0);
  re_->BeginFrame(0);
  re_->ClearScene();
  re_->RenderScene(&view);
  re_->EndFrame(nullptr, nullptr);
  EXPECT_TRUE(fake::engine().printed("prepared shaders"));
  EXPECT_EQ(fake::engine().lastErrorLevel, -1);
}

TEST_F(ModuleTest, EndRegistrationMakesTheWorldSpritesMaterials) {
  // The shaders of a map's autosprite surfaces (oa_shouse: flames, a fireball, smoke) are
  // registered by the module alone, not by the game: EndRegistration registers them and makes
  // their materials with the others', so that the first views of play make none.
  if (!fake::mountInstalledGame()) GTEST_SKIP() << "OpenArena data not installed";
  fake::engine().setCvar("developer", "1");
  fake::engine().setCvar("r_pt_preset", "direct");
  begin();
  re_->LoadWorld("maps/oa_shouse.bsp");
  re_->EndRegistration();
  EXPECT_EQ(fake::engine().lastErrorLevel, -1);
  fake::engine().prints.clear();
  q3abi::refdef_t view{};
  view.width = 64;
  view.height = 36;
  view.fov_x = 90.0f;
  view.fov_y = 59.0f;
  view.viewaxis[0][0] = view.viewaxis[1][1] = view.viewaxis[2][2] = 1.0f;
  for (int frame = 0; frame < 3; ++frame) {
    re_->BeginFrame(0);
    re_->ClearScene();
    re_->RenderScene(&view);
    re_->EndFrame(nullptr, nullptr);
  }
  EXPECT_FALSE(fake::engine().printed("prepared shaders")) << "a view of play made materials";
  EXPECT_EQ(fake::engine().lastErrorLevel, -1);
}

TEST_F(ModuleTest, StatsDescribeASlowFrameWithItsPhases) {
  // r_pt_stats: a frame of play (one that draws a view) of 50 ms or more, a hitch, is printed
  // with its phases; a slow frame without a view (a loading screen) is the engine's and is not.
  fake::engine().setCvar("r_pt_stats", "1");
  begin();
  const q3abi::refdef_t view = modelView(32);
  const auto frame = [&](bool drawView, int sleepMs) {
    re_->BeginFrame(0);
    if (drawView) {
      re_->ClearScene();
      re_->RenderScene(&view);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(sleepMs));   // the game taking its time
    re_->EndFrame(nullptr, nullptr);
  };
  frame(false, 0);
  frame(false, 70);   // frame 2: slow, no view
  fake::engine().prints.clear();
  frame(true, 70);    // frame 3: slow, a HUD model view (frame 2 is judged as it begins)
  frame(false, 0);    // and frame 3 as this one begins
  EXPECT_FALSE(fake::engine().printed("pathtracer: slow frame 2: ")) << "a loading frame described";
  EXPECT_TRUE(fake::engine().printed("pathtracer: slow frame 3: ")) << "no slow frame described";
  EXPECT_TRUE(fake::engine().printed(" model_views=1 "));
  EXPECT_TRUE(fake::engine().printed(" engine_ms="));
}

TEST_F(ModuleTest, WorldViewWithoutAWorldDropsToTheMenu) {
  begin();
  re_->BeginFrame(0);
  q3abi::refdef_t view{};
  view.width = view.height = 64;
  view.fov_x = view.fov_y = 90.0f;
  fake::FakeEngine& e = fake::engine();
  e.errorJumpArmed = true;
  if (setjmp(e.errorJump) == 0) {
    re_->RenderScene(&view);
    ADD_FAILURE() << "RenderScene returned instead of calling ri.Error";
  }
  EXPECT_EQ(e.lastErrorLevel, q3abi::ERR_DROP);
  EXPECT_NE(e.lastError.find("no world"), std::string::npos);
  re_->EndFrame(nullptr, nullptr);   // the module is still usable afterwards
}

TEST_F(ModuleTest, MissingMapDropsWithItsName) {
  begin();
  fake::FakeEngine& e = fake::engine();
  e.errorJumpArmed = true;
  if (setjmp(e.errorJump) == 0) {
    re_->LoadWorld("maps/nowhere.bsp");
    ADD_FAILURE() << "LoadWorld returned";
  }
  EXPECT_EQ(e.lastErrorLevel, q3abi::ERR_DROP);
  EXPECT_NE(e.lastError.find("maps/nowhere.bsp"), std::string::npos);
}

TEST_F(ModuleTest, MalformedMapDropsNamingTheFileAndField) {
  begin();
  fake::FakeEngine& e = fake::engine();
  // A valid header whose surfaces lump points far outside the file.
  std::vector<uint8_t> bsp(8 + 17 * 8, 0);
  std::memcpy(bsp.data(), "IBSP", 4);
  bsp[4] = 46;
  const int32_t outside = 1 << 30, length = 104;
  std::memcpy(bsp.data() + 8 + 13 * 8, &outside, 4);
  std::memcpy(bsp.data() + 12 + 13 * 8, &length, 4);
  e.files["maps/broken.bsp"] = bsp;
  e.errorJumpArmed = true;
  if (setjmp(e.errorJump) == 0) {
    re_->LoadWorld("maps/broken.bsp");
    ADD_FAILURE() << "LoadWorld returned";
  }
  EXPECT_EQ(e.lastErrorLevel, q3abi::ERR_DROP);
  EXPECT_NE(e.lastError.find("maps/broken.bsp"), std::string::npos) << e.lastError;
  EXPECT_NE(e.lastError.find("surfaces"), std::string::npos) << e.lastError;
}

TEST_F(ModuleTest, MapWithExternalLightmapsLoadsAsInTheStockRenderer) {
  begin();
  fake::FakeEngine& e = fake::engine();
  const auto asBytes = [](const std::vector<std::byte>& in) {
    std::vector<uint8_t> out(in.size());
    std::memcpy(out.data(), in.data(), in.size());
    return out;
  };
  // q3map2 -external: an empty lightmap lump, lightmap number 0 = maps/ext/lm_0000.tga.
  e.files["maps/ext.bsp"] = asBytes(q3::testing::externalLightmapMap(0).build());
  e.files["maps/ext/lm_0000.tga"] =
      asBytes(q3::testing::tga24(4, 4, [](int, int) { return std::array<uint8_t, 3>{0, 64, 0}; }));
  re_->LoadWorld("maps/ext.bsp");
  EXPECT_TRUE(e.printed("loaded maps/ext.bsp"));
  EXPECT_FALSE(e.printed("selects none"));
  re_->Shutdown(0);
  // Without the image the map still loads, vertex-lit, with one warning.
  e.files.erase("maps/ext/lm_0000.tga");
  begin();
  re_->LoadWorld("maps/ext.bsp");
  EXPECT_TRUE(e.printed("selects none"));
}

TEST_F(ModuleTest, ScreenshotNamesFollowTheEngineConvention) {
  begin();
  re_->BeginFrame(0);
  EXPECT_TRUE(fake::engine().runCommand({"screenshot"}));
  EXPECT_TRUE(fake::engine().runCommand({"screenshotJPEG"}));
  re_->EndFrame(nullptr, nullptr);
  EXPECT_TRUE(fake::engine().written.count("screenshots/shot0000.tga"));
  EXPECT_TRUE(fake::engine().written.count("screenshots/shot0001.jpg"));
  EXPECT_TRUE(fake::engine().printed("Wrote screenshots/shot0001.jpg"));
}

TEST_F(ModuleTest, RealMapLoadsAndAnswersQueries) {
  if (!fake::mountInstalledGame()) GTEST_SKIP() << "OpenArena data not installed";
  begin();
  re_->LoadWorld("maps/oa_dm1.bsp");
  EXPECT_TRUE(fake::engine().printed("loaded maps/oa_dm1.bsp"));
  char token[256];
  ASSERT_EQ(re_->GetEntityToken(token, sizeof token), 1);
  EXPECT_STREQ(token, "{");
  // Find a spawn point from the entity string and query around it.
  float spawn[3] = {0, 0, 0};
  bool found = false, inSpawn = false;
  while (!found && re_->GetEntityToken(token, sizeof token)) {
    if (std::strcmp(token, "info_player_deathmatch") == 0) inSpawn = true;
    if (std::strcmp(token, "{") == 0) inSpawn = false;
    if (std::strcmp(token, "origin") == 0) {
      char value[256];
      re_->GetEntityToken(value, sizeof value);
      std::sscanf(value, "%f %f %f", &spawn[0], &spawn[1], &spawn[2]);
      // The key order varies: remember the last origin and accept it once the class matches.
      if (inSpawn) found = true;
    }
  }
  if (!found) GTEST_SKIP() << "no spawn with origin after classname";
  float ambient[3], directed[3], dir[3];
  EXPECT_EQ(re_->LightForPoint(spawn, ambient, directed, dir), 1);
  EXPECT_GT(ambient[0] + ambient[1] + ambient[2] + directed[0] + directed[1] + directed[2], 0.0f);
  EXPECT_NEAR(std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]), 1.0f, 1e-3f);
  EXPECT_EQ(re_->inPVS(spawn, spawn), 1);
  const float far[3] = {1e6f, 1e6f, 1e6f};
  EXPECT_EQ(re_->inPVS(spawn, far), 0);
  // A decal projected down onto the floor under the spawn point, wound clockwise seen along
  // the projection as the cgame's CG_ImpactMark does (the other winding clips everything).
  const q3abi::vec3_t quad[4] = {{spawn[0] - 8, spawn[1] - 8, spawn[2] - 20},
                                 {spawn[0] - 8, spawn[1] + 8, spawn[2] - 20},
                                 {spawn[0] + 8, spawn[1] + 8, spawn[2] - 20},
                                 {spawn[0] + 8, spawn[1] - 8, spawn[2] - 20}};
  const float down[3] = {0, 0, -64};
  q3abi::vec3_t points[384];
  q3abi::markFragment_t fragments[128];
  const int count = re_->MarkFragments(4, quad, down, 384, points[0], 128, fragments);
  EXPECT_GE(count, 1);
  for (int i = 0; i < count; ++i) {
    EXPECT_GE(fragments[i].numPoints, 3);
    for (int p = 0; p < fragments[i].numPoints; ++p) {
      const float* v = points[fragments[i].firstPoint + p];
      EXPECT_LE(std::fabs(v[0] - spawn[0]), 8.01f);
      EXPECT_LE(std::fabs(v[1] - spawn[1]), 8.01f);
    }
  }
  const q3abi::qhandle_t door = re_->RegisterModel("*1");
  EXPECT_GT(door, 0);
  float mins[3], maxs[3];
  re_->ModelBounds(door, mins, maxs);   // oa_dm1's model 1, as stored in the models lump
  EXPECT_EQ(mins[0], -400.0f);
  EXPECT_EQ(mins[1], 1560.0f);
  EXPECT_EQ(mins[2], -4.0f);
  EXPECT_EQ(maxs[0], -336.0f);
  EXPECT_EQ(maxs[1], 1624.0f);
  EXPECT_EQ(maxs[2], 4.0f);
  EXPECT_EQ(re_->RegisterModel("*9999"), 0);
  re_->EndRegistration();
  re_->Shutdown(0);
  re_->Shutdown(0);
  begin();
  re_->LoadWorld("maps/oa_dm1.bsp");   // a second load after Shutdown(0)
}

}  // namespace
