// r_pt_captureExr's film copy and EXR bytes read back by pa-regress's noise-aware comparison.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "port/engine_glue/capture_exr.h"
#include "tests/regress/compare/noise_test.h"

namespace {

TEST(CaptureExr, FilmOfAPictureReadsBackAsWritten) {
  const std::vector<glm::vec3> radiance = {{0.5f, 1.0f, 2.0f}, {0.0f, 0.25f, 8.0f}, {3.0f, 0.0f, 0.125f},
                                           {1e-3f, 10.0f, 0.75f}, {0.0f, 0.0f, 0.0f}, {100.0f, 50.0f, 25.0f}};
  const std::vector<float> variance = {0.0f, 0.5f, 1e-4f, 2.0f, 0.0f, 7.0f};
  glue::TracedPicture picture;
  picture.width = 6;   // shown at the window's size (TAAU); the film is the traced size
  picture.height = 4;
  picture.filmWidth = 3;
  picture.filmHeight = 2;
  picture.radiance = radiance;
  picture.variance = variance;
  glue::FilmCapture film;
  film.assign(picture);
  ASSERT_FALSE(film.empty());
  const std::vector<uint8_t> bytes = glue::encodeFilmExr(film);
  ASSERT_FALSE(bytes.empty());
  const auto path = std::filesystem::temp_directory_path() / "pa_capture_exr_test.exr";
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  const pa::regress::HdrImage image = pa::regress::loadExr(path.string());
  std::filesystem::remove(path);
  ASSERT_EQ(image.width, 3);
  ASSERT_EQ(image.height, 2);
  for (size_t i = 0; i < radiance.size(); ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(image.rgb[i * 3 + c], radiance[i][c]) << "pixel " << i << " channel " << c;
    EXPECT_EQ(image.varianceY[i], variance[i]) << "pixel " << i;
  }
}

TEST(CaptureExr, APictureWithoutAFilmLeavesNothing) {
  glue::TracedPicture picture;
  picture.width = 4;
  picture.height = 4;
  picture.filmWidth = 4;
  picture.filmHeight = 4;   // no radiance: a build without the tracer, or a picture of another size
  glue::FilmCapture film;
  film.assign(picture);
  EXPECT_TRUE(film.empty());
  EXPECT_TRUE(glue::encodeFilmExr(film).empty());
}

}  // namespace
