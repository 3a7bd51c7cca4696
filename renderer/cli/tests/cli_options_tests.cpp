// pa-render command-line parsing.
#include <gtest/gtest.h>

#include <vector>

#include "renderer/cli/cli_options.h"

namespace pa::cli {
namespace {

ParseResult parse(std::vector<std::string_view> args) { return parseCommandLine(args); }

TEST(CliOptions, MinimalCommandUsesDefaults) {
  const ParseResult r = parse({"scene.gltf", "-o", "out.png"});
  ASSERT_EQ(r.status, ParseStatus::Ok) << r.message;
  EXPECT_EQ(r.options.scene, "scene.gltf");
  EXPECT_EQ(r.options.pngOut, "out.png");
  EXPECT_FALSE(r.options.exrOut.has_value());
  EXPECT_FALSE(r.options.statsOut.has_value());
  EXPECT_FALSE(r.options.denoise);
  EXPECT_FALSE(r.options.restir);
  EXPECT_EQ(r.options.play, CliOptions::Play::Accumulate);
  EXPECT_EQ(r.options.width, 0u);
  EXPECT_EQ(r.options.samplesPerPixel, 16u);
  EXPECT_EQ(r.options.frames, 1u);
  EXPECT_EQ(r.options.bounces, 4u);
  EXPECT_EQ(r.options.rouletteStart, 3u);
  ASSERT_EQ(r.options.integrators.size(), 1u);
  EXPECT_EQ(r.options.integrators[0].integrator, Integrator::Path);
  EXPECT_EQ(r.options.integrators[0].samplesPerPixel, 0u);
  EXPECT_EQ(r.options.tonemap, Tonemap::AcesFitted);
  EXPECT_EQ(r.options.lighting, LightingLook::Physical);
  EXPECT_FLOAT_EQ(r.options.exposure, 1.0f);
}

TEST(CliOptions, ParsesEveryOption) {
  const ParseResult r = parse({"--width", "320", "--height=200", "--spp", "8", "--bounces", "2", "--seed", "42",
                               "--threads", "3", "--integrator", "direct", "--camera", "1", "--clamp", "10.5",
                               "--exposure=2", "--frames", "5", "--exr", "o.exr", "--light-scale", "0.001",
                               "--stats", "s.json", "--progress", "--tonemap", "clamp", "map.glb", "--output", "o.png",
                               "--denoise", "--play", "temporal", "--restir", "--lighting", "display",
                               "--spread-fireflies", "--baked-path-end", "--roulette-start", "1"});
  ASSERT_EQ(r.status, ParseStatus::Ok) << r.message;
  const CliOptions& o = r.options;
  EXPECT_EQ(o.play, CliOptions::Play::Temporal);
  EXPECT_EQ(o.scene, "map.glb");
  EXPECT_EQ(o.pngOut, "o.png");
  EXPECT_EQ(o.exrOut, std::filesystem::path("o.exr"));
  EXPECT_EQ(o.statsOut, std::filesystem::path("s.json"));
  EXPECT_EQ(o.width, 320u);
  EXPECT_EQ(o.height, 200u);
  EXPECT_EQ(o.samplesPerPixel, 8u);
  EXPECT_EQ(o.bounces, 2u);
  EXPECT_EQ(o.rouletteStart, 1u);
  EXPECT_EQ(o.seed, 42u);
  EXPECT_EQ(o.threads, 3u);
  ASSERT_EQ(o.integrators.size(), 1u);
  EXPECT_EQ(o.integrators[0].integrator, Integrator::Direct);
  EXPECT_EQ(o.camera, 1u);
  EXPECT_FLOAT_EQ(o.clamp, 10.5f);
  EXPECT_FLOAT_EQ(o.exposure, 2.0f);
  EXPECT_EQ(o.frames, 5u);
  EXPECT_FLOAT_EQ(o.lightScale, 0.001f);
  EXPECT_TRUE(o.progress);
  EXPECT_EQ(o.tonemap, Tonemap::Clamp);
  EXPECT_EQ(o.lighting, LightingLook::DisplaySpace);
  EXPECT_TRUE(o.spreadFireflies);
  EXPECT_TRUE(o.denoise);
  EXPECT_TRUE(o.restir);
  EXPECT_TRUE(o.bakedPathEnd);
}

TEST(CliOptions, ExposureAutoMetersTheImage) {
  const ParseResult r = parse({"map.glb", "-o", "o.png", "--exposure", "auto"});
  ASSERT_EQ(r.status, ParseStatus::Ok) << r.message;
  EXPECT_TRUE(r.options.autoExposure);
  EXPECT_FALSE(parse({"map.glb", "-o", "o.png", "--exposure", "auto", "--exposure", "3"}).options.autoExposure);
  EXPECT_FALSE(parse({"map.glb", "-o", "o.png"}).options.autoExposure);
}

TEST(CliOptions, HelpWinsOverEverythingElse) {
  EXPECT_EQ(parse({"--help"}).status, ParseStatus::Help);
  EXPECT_EQ(parse({"scene.gltf", "--bogus", "-h"}).status, ParseStatus::Error);  // first error stops parsing
  EXPECT_EQ(parse({"-h", "--bogus"}).status, ParseStatus::Help);
}

TEST(CliOptions, RejectsBadInputWithAMessageNamingTheOption) {
  struct Case {
    std::vector<std::string_view> args;
    const char* expected;
  };
  const std::vector<Case> cases = {
      {{}, "missing input scene"},
      {{"a.gltf"}, "missing -o"},
      {{"a.gltf", "b.gltf", "-o", "x.png"}, "expected one input scene"},
      {{"a.gltf", "-o"}, "-o: missing value"},
      {{"a.gltf", "-o", "x.png", "--width", "0"}, "--width: expected an integer in [1, 16384]"},
      {{"a.gltf", "-o", "x.png", "--width", "12abc"}, "--width"},
      {{"a.gltf", "-o", "x.png", "--height", "-5"}, "--height"},
      {{"a.gltf", "-o", "x.png", "--spp", "0"}, "--spp"},
      {{"a.gltf", "-o", "x.png", "--frames", "0"}, "--frames"},
      {{"a.gltf", "-o", "x.png", "--seed", "99999999999"}, "--seed"},
      {{"a.gltf", "-o", "x.png", "--exposure", "0"}, "--exposure: expected a number > 0"},
      {{"a.gltf", "-o", "x.png", "--exposure", "automatic"}, "or \"auto\""},
      {{"a.gltf", "-o", "x.png", "--clamp", "nan"}, "--clamp"},
      {{"a.gltf", "-o", "x.png", "--clamp", "-1"}, "--clamp"},
      {{"a.gltf", "-o", "x.png", "--integrator", "whitted"}, "--integrator: expected lightmap, direct or path"},
      {{"a.gltf", "-o", "x.png", "--integrator", "direct,"}, "--integrator: expected lightmap, direct or path, got \"\""},
      {{"a.gltf", "-o", "x.png", "--integrator", "path,direct,path"}, "--integrator: path given twice"},
      {{"a.gltf", "-o", "x.png", "--integrator", "direct:0"}, "--integrator direct:SPP: expected an integer in [1,"},
      {{"a.gltf", "-o", "x.png", "--integrator", "direct:8x"}, "--integrator direct:SPP"},
      {{"a.gltf", "-o", "x.png", "--tonemap", "filmic"}, "--tonemap: expected aces, reinhard or clamp"},
      {{"a.gltf", "-o", "x.png", "--lighting", "gamma"}, "--lighting: expected physical or display"},
      {{"a.gltf", "-o", "x.png", "--frobnicate", "1"}, "unknown option --frobnicate"},
      {{"a.gltf", "-o", "x.png", "--progress=1"}, "--progress takes no value"},
      {{"a.gltf", "-o", "x.png", "--denoise=1"}, "--denoise takes no value"},
      {{"a.gltf", "-o", "x.png", "--play", "loop"}, "--play: expected accumulate, independent or temporal"},
      {{"a.gltf", "-o", "x.png", "--progress", "--quiet"}, "contradict"},
  };
  for (const Case& c : cases) {
    const ParseResult r = parseCommandLine(c.args);
    EXPECT_EQ(r.status, ParseStatus::Error) << c.expected;
    EXPECT_NE(r.message.find(c.expected), std::string::npos) << "got: " << r.message;
  }
}

TEST(CliOptions, IntegratorListInOrderWithTheirOwnSamplesAndNamedOutputs) {
  const ParseResult r = parse({"m.bsp", "-o", "out/pic.png", "--exr", "pic.exr", "--spp", "6", "--integrator",
                               "path:16,lightmap,direct:1"});
  ASSERT_EQ(r.status, ParseStatus::Ok) << r.message;
  const CliOptions& o = r.options;
  ASSERT_EQ(o.integrators.size(), 3u);
  EXPECT_EQ(o.integrators[0].integrator, Integrator::Path);
  EXPECT_EQ(o.integrators[1].integrator, Integrator::Lightmap);
  EXPECT_EQ(o.integrators[2].integrator, Integrator::Direct);
  EXPECT_EQ(samplesPerPixelOf(o, o.integrators[0]), 16u);
  EXPECT_EQ(samplesPerPixelOf(o, o.integrators[1]), 6u);   // --spp
  EXPECT_EQ(samplesPerPixelOf(o, o.integrators[2]), 1u);
  EXPECT_EQ(outputPathFor(o.pngOut, o, Integrator::Direct), std::filesystem::path("out/pic_direct.png"));
  EXPECT_EQ(outputPathFor(*o.exrOut, o, Integrator::Lightmap), std::filesystem::path("pic_lightmap.exr"));

  const ParseResult single = parse({"m.bsp", "-o", "pic.png", "--integrator", "direct:4"});
  ASSERT_EQ(single.status, ParseStatus::Ok) << single.message;
  ASSERT_EQ(single.options.integrators.size(), 1u);
  EXPECT_EQ(samplesPerPixelOf(single.options, single.options.integrators[0]), 4u);
  EXPECT_EQ(outputPathFor(single.options.pngOut, single.options, Integrator::Direct), std::filesystem::path("pic.png"));
}

TEST(CliOptions, DoubleDashEndsOptions) {
  const ParseResult r = parse({"-o", "x.png", "--", "-weird-name.gltf"});
  ASSERT_EQ(r.status, ParseStatus::Ok) << r.message;
  EXPECT_EQ(r.options.scene, "-weird-name.gltf");
}

TEST(CliOptions, UsageDocumentsEveryOption) {
  const std::string usage = usageText("pa-render");
  for (const char* option : {"-o", "--exr", "--stats", "--width", "--height", "--spp", "--bounces", "--roulette-start", "--seed",
                             "--threads", "--integrator", "--camera", "--clamp", "--exposure", "--tonemap", "--lighting", "--frames", "--light-scale",
                             "--progress", "--quiet", "--denoise", "--spread-fireflies", "--play", "--help", "Exit status"})
    EXPECT_NE(usage.find(option), std::string::npos) << option;
}

}  // namespace
}  // namespace pa::cli
