// pa-render end to end: the bundled scene rendered tiny, exit codes and messages.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <stb_image.h>
#include <tinyexr.h>

namespace {

namespace fs = std::filesystem;

/// Runs pa-render with `arguments`; returns its exit code and fills `log` with stdout+stderr.
int runPaRender(const std::string& arguments, std::string& log) {
  const fs::path logPath = fs::temp_directory_path() / ("pa_render_log_" + std::to_string(::getpid()) + ".txt");
  const std::string command = std::string("\"") + PA_RENDER + "\" " + arguments + " > \"" + logPath.string() + "\" 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(logPath);
  log.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  fs::remove(logPath);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class PaRenderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("pa_render_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  std::string arena() const { return std::string("\"") + PA_DEFAULT_ARENA + "\""; }
  fs::path dir_;
};

std::vector<uint8_t> loadRgb(const std::string& path, int& width, int& height) {
  int channels = 0;
  stbi_uc* pixels = stbi_load(path.c_str(), &width, &height, &channels, 3);
  if (!pixels) return {};
  std::vector<uint8_t> rgb(pixels, pixels + size_t(width) * height * 3);
  stbi_image_free(pixels);
  return rgb;
}

TEST_F(PaRenderTest, RendersTheDefaultArenaTiny) {
  std::string log;
  const std::string png = file("nested/arena.png");
  ASSERT_EQ(runPaRender(arena() + " -o " + png + " --width 64 --height 36 --spp 2 --exr " + file("arena.exr"), log), 0)
      << log;
  EXPECT_NE(log.find("64x36"), std::string::npos) << log;           // the summary line
  int width = 0, height = 0;
  const std::vector<uint8_t> rgb = loadRgb(png, width, height);
  ASSERT_FALSE(rgb.empty());
  EXPECT_EQ(width, 64);
  EXPECT_EQ(height, 36);
  double sum = 0.0;
  std::set<uint32_t> colours;
  for (size_t i = 0; i + 2 < rgb.size(); i += 3) {
    sum += rgb[i] + rgb[i + 1] + rgb[i + 2];
    colours.insert(uint32_t(rgb[i]) << 16 | uint32_t(rgb[i + 1]) << 8 | rgb[i + 2]);
  }
  const double mean = sum / rgb.size();
  EXPECT_GT(mean, 20.0) << "image is (nearly) black";
  EXPECT_LT(mean, 245.0) << "image is (nearly) white";
  EXPECT_GT(colours.size(), 100u) << "image is (nearly) uniform";

  EXRVersion version;
  ASSERT_EQ(ParseEXRVersionFromFile(&version, file("arena.exr").c_str()), TINYEXR_SUCCESS);
  EXRHeader header;
  InitEXRHeader(&header);
  const char* error = nullptr;
  ASSERT_EQ(ParseEXRHeaderFromFile(&header, &version, file("arena.exr").c_str(), &error), TINYEXR_SUCCESS);
  EXPECT_EQ(header.num_channels, 11);
  FreeEXRHeader(&header);
}

TEST_F(PaRenderTest, StatsJsonDescribesTheRenderAndCountsSkyPixelsOfTheDepthAov) {
  std::string log;
  ASSERT_EQ(runPaRender(arena() + " -o " + file("s.png") + " --width 40 --height 24 --spp 1 --integrator direct --exr " +
                            file("s.exr") + " --stats " + file("out/s.json"),
                        log),
            0)
      << log;
  std::ifstream in(file("out/s.json"));
  ASSERT_TRUE(in.good());
  const nlohmann::json stats = nlohmann::json::parse(in);
  EXPECT_EQ(stats.at("width"), 40);
  EXPECT_EQ(stats.at("height"), 24);
  EXPECT_EQ(stats.at("integrator"), "direct");
  EXPECT_EQ(stats.at("tonemap"), "aces");
  EXPECT_EQ(stats.at("exposure"), 1.0);
  EXPECT_EQ(stats.at("spp"), 1);
  EXPECT_EQ(stats.at("frames"), 1);
  EXPECT_EQ(stats.at("camera_index"), 0);
  EXPECT_GT(stats.at("triangles").get<int>(), 0);
  EXPECT_GE(stats.at("lights").get<int>(), 1);
  EXPECT_GE(stats.at("render_seconds").get<double>(), 0.0);
  EXPECT_GE(stats.at("first_frame_seconds").get<double>(), 0.0);   // one frame: the whole render
  EXPECT_LE(stats.at("first_frame_seconds").get<double>(), stats.at("render_seconds").get<double>());

  EXRVersion version;
  ASSERT_EQ(ParseEXRVersionFromFile(&version, file("s.exr").c_str()), TINYEXR_SUCCESS);
  EXRHeader header;
  InitEXRHeader(&header);
  const char* error = nullptr;
  ASSERT_EQ(ParseEXRHeaderFromFile(&header, &version, file("s.exr").c_str(), &error), TINYEXR_SUCCESS);
  for (int c = 0; c < header.num_channels; ++c) header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
  EXRImage image;
  InitEXRImage(&image);
  ASSERT_EQ(LoadEXRImageFromFile(&image, &header, file("s.exr").c_str(), &error), TINYEXR_SUCCESS);
  int sky = 0;
  for (int c = 0; c < header.num_channels; ++c) {
    if (std::string(header.channels[c].name) != "Z") continue;
    const float* z = reinterpret_cast<const float*>(image.images[c]);
    for (int i = 0; i < image.width * image.height; ++i) sky += std::isfinite(z[i]) ? 0 : 1;
  }
  const int pixels = image.width * image.height;
  FreeEXRImage(&image);
  FreeEXRHeader(&header);
  EXPECT_GT(sky, 0) << "the bundled camera sees the sky through the window";
  EXPECT_DOUBLE_EQ(stats.at("sky_fraction").get<double>(), double(sky) / double(pixels));
}

TEST_F(PaRenderTest, ImageDoesNotDependOnThreadCount) {
  std::string log;
  const std::string common = arena() + " --width 48 --height 27 --spp 1 --frames 2 --seed 7 -o ";
  ASSERT_EQ(runPaRender(common + file("one.png") + " --threads 1", log), 0) << log;
  ASSERT_EQ(runPaRender(common + file("two.png") + " --threads 2", log), 0) << log;
  int w1 = 0, h1 = 0, w2 = 0, h2 = 0;
  const std::vector<uint8_t> one = loadRgb(file("one.png"), w1, h1);
  const std::vector<uint8_t> two = loadRgb(file("two.png"), w2, h2);
  ASSERT_FALSE(one.empty());
  EXPECT_EQ(one, two);
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST_F(PaRenderTest, SeveralIntegratorsOverOneLoadMakeTheSamePicturesAsOneRunEach) {
  // Played frames with temporal accumulation and reservoirs: history one integrator left behind
  // would show in the next one's pictures. --exposure auto meters the first and exposes all.
  std::string log;
  const std::string common = arena() + " --width 48 --height 27 --frames 3 --play temporal --restir --seed 5 --threads 2";
  ASSERT_EQ(runPaRender(common + " --integrator lightmap:2,direct,path:3 --spp 2 --exposure auto -o " +
                            file("all.png") + " --exr " + file("all.exr") + " --stats " + file("all.json"),
                        log),
            0)
      << log;
  std::ifstream lightmapStats(file("all_lightmap.json"));
  const nlohmann::json metered = nlohmann::json::parse(lightmapStats);
  const double gain = metered.at("exposure").get<double>();
  ASSERT_TRUE(metered.at("auto_exposure").is_object());
  EXPECT_DOUBLE_EQ(metered.at("auto_exposure").at("gain").get<double>(), gain);
  char gainText[32];
  std::snprintf(gainText, sizeof gainText, "%.9g", gain);

  struct Run { const char* name; const char* spp; const char* exposure; };
  for (const Run run : {Run{"lightmap", "2", "auto"}, Run{"direct", "2", gainText}, Run{"path", "3", gainText}}) {
    SCOPED_TRACE(run.name);
    const std::string one = file(std::string("one_") + run.name);
    ASSERT_EQ(runPaRender(common + " --integrator " + run.name + " --spp " + run.spp + " --exposure " + run.exposure +
                              " -o " + one + ".png --exr " + one + ".exr",
                          log),
              0)
        << log;
    const std::string all = file(std::string("all_") + run.name);
    EXPECT_EQ(fileBytes(all + ".png"), fileBytes(one + ".png"));
    EXPECT_EQ(fileBytes(all + ".exr"), fileBytes(one + ".exr"));
    EXPECT_FALSE(fileBytes(all + ".png").empty());
    std::ifstream statsFile(all + ".json");
    const nlohmann::json stats = nlohmann::json::parse(statsFile);
    EXPECT_EQ(stats.at("integrator"), run.name);
    EXPECT_EQ(stats.at("spp"), std::atoi(run.spp));
    EXPECT_DOUBLE_EQ(stats.at("exposure").get<double>(), gain);
    EXPECT_EQ(stats.at("auto_exposure").at("metered_on"), "lightmap");
  }
  EXPECT_FALSE(fs::exists(file("all.png")));   // with several integrators every name carries one
}

TEST_F(PaRenderTest, ExitCodesAndMessages) {
  std::string log;
  EXPECT_EQ(runPaRender("--help", log), 0);
  EXPECT_NE(log.find("Usage: pa-render"), std::string::npos) << log;
  EXPECT_EQ(runPaRender("", log), 2);
  EXPECT_NE(log.find("missing input scene"), std::string::npos) << log;
  EXPECT_EQ(runPaRender(arena() + " -o x.png --spp zero", log), 2);
  EXPECT_NE(log.find("--spp"), std::string::npos) << log;
  EXPECT_EQ(runPaRender(file("scene.obj") + " -o " + file("x.png"), log), 2);
  EXPECT_NE(log.find("unknown scene format"), std::string::npos) << log;
  EXPECT_EQ(runPaRender(file("missing.gltf") + " -o " + file("x.png"), log), 1);
  EXPECT_NE(log.find("missing.gltf: cannot open"), std::string::npos) << log;
  std::ofstream(file("broken.glb"), std::ios::binary) << "glTF-but-not-really";
  EXPECT_EQ(runPaRender(file("broken.glb") + " -o " + file("x.png"), log), 1);
  EXPECT_NE(log.find("broken.glb"), std::string::npos) << log;
  EXPECT_EQ(runPaRender(arena() + " -o " + file("x.png") + " --camera 3 --width 8 --height 8", log), 1);
  EXPECT_NE(log.find("--camera 3 out of range"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(file("x.png")));
}

}  // namespace
