// Reservoir resampling (ReSTIR DI) against the plain integrator on a many-light scene with
// occluders: its mean is the plain mean, its single frames are closer to it, and its image does
// not depend on the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "renderer/scene/renderer.h"
#include "scene_builders.h"

namespace pa {
namespace {

using test::lookAt;
using test::settingsFor;

constexpr uint32_t kSize = 40;

/// A floor cut into rooms by walls with gaps, 72 lamps (point, spot, sphere) of mixed strength
/// above it, an emissive panel, a sun and a sky: most lamps are behind a wall from most points.
void buildManyLights(Renderer& r) {
  const MaterialId grey = r.addMaterial(test::diffuse(0.6f));
  MaterialDesc shiny = test::diffuse(0.5f);
  shiny.specular = 0.4f;
  shiny.roughness = 0.3f;
  const MaterialId glossy = r.addMaterial(shiny);
  MaterialDesc panel;
  panel.emission = glm::vec3(3.0f);
  const MaterialId glow = r.addMaterial(panel);
  test::addMesh(r, test::quad({-8, -8, 0}, {16, 0, 0}, {0, 16, 0}), grey);
  for (float x : {-4.0f, 0.0f, 4.0f}) {   // walls along y with a gap in the middle
    test::addMesh(r, test::quad({x, -8, 0}, {0, 7, 0}, {0, 0, 2.5f}), grey);
    test::addMesh(r, test::quad({x, 1.5f, 0}, {0, 6.5f, 0}, {0, 0, 2.5f}), glossy);
  }
  test::addMesh(r, test::quad({-8, 0, 0}, {6, 0, 0}, {0, 0, 2.0f}), grey);   // a wall along x
  test::addMesh(r, test::sphere({2, -3, 0.8f}, 0.8f, 8, 16), glossy);
  test::addMesh(r, test::quad({-6.5f, 5, 2.2f}, {0, 1, 0}, {1, 0, 0}), glow);   // faces down
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 8; ++j) {
      LightDesc l;
      l.position = {-7.2f + 1.8f * i, -7.0f + 2.0f * j, 1.0f + 0.15f * ((i + j) % 4)};
      l.intensity = 0.3f + 0.25f * ((i * 7 + j * 3) % 9);
      if ((i + j) % 5 == 0) {
        l.type = LightType::Spot;
        l.direction = {0, 0, -1};
        l.cosInnerAngle = 0.9f;
        l.cosOuterAngle = 0.7f;
      } else if ((i + 2 * j) % 7 == 0) {
        l.radius = 0.15f;
      }
      r.addLight(l);
    }
  }
  LightDesc sun;
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, 0.2f, -1.0f));
  sun.intensity = 0.4f;
  r.addLight(sun);
  SkyDesc sky;
  sky.color = glm::vec3(0.15f);
  r.setSky(sky);
  r.commit();
}

Camera camera() { return lookAt({0, -13, 11}, {0, -1, 0}, 60.0f); }

/// A narrow view of the same scene: neighbouring pixels' hits lie close together against the
/// lamps' distances, as in a game view at 320 x 180 (1/Z spatial reuse is noisy otherwise:
/// README.md).
Camera narrowCamera() { return lookAt({0, -13, 11}, {-1, -2, 0}, 14.0f); }

double meanGreen(const FrameView& f) {
  double sum = 0.0;
  for (const glm::vec3& c : f.radiance) sum += c.g;
  return sum / static_cast<double>(f.radiance.size());
}

/// Image means of `runs` independent ReSTIR runs (seeds differ), each accumulating `frames`
/// frames with the reservoirs' history.
std::vector<double> restirMeans(RenderSettings s, uint32_t runs, uint32_t frames) {
  std::vector<double> means;
  for (uint32_t k = 0; k < runs; ++k) {
    Renderer r({2});
    buildManyLights(r);
    s.seed = 1000 + k;
    s.restir = true;
    FrameView f;
    for (uint32_t i = 0; i < frames; ++i) f = r.render(camera(), s);
    means.push_back(meanGreen(f));
  }
  return means;
}

void expectSameMean(Integrator integrator, uint32_t bounces, uint32_t referenceSpp) {
  Renderer plain({2});
  buildManyLights(plain);
  const FrameView reference = plain.render(camera(), settingsFor(integrator, kSize, referenceSpp, bounces));
  const test::FrameStats ref = test::greyStats(reference);
  const std::vector<double> means = restirMeans(settingsFor(integrator, kSize, 1, bounces), 12, 4);
  double mean = 0.0, squares = 0.0;
  for (double m : means) mean += m;
  mean /= static_cast<double>(means.size());
  for (double m : means) squares += (m - mean) * (m - mean);
  const double restirError = std::sqrt(squares / static_cast<double>(means.size() - 1) / static_cast<double>(means.size()));
  const double bound = 4.0 * std::sqrt(restirError * restirError + ref.standardError * ref.standardError);
  EXPECT_NEAR(mean, ref.mean, bound) << "plain " << ref.mean << " +- " << ref.standardError << ", restir " << mean
                                     << " +- " << restirError;
  EXPECT_GT(ref.mean, 0.0);
}

TEST(Restir, DirectMeanIsThePlainIntegratorsOnAManyLightScene) { expectSameMean(Integrator::Direct, 4, 1024); }

TEST(Restir, PathMeanIsThePlainIntegratorsOnAManyLightScene) { expectSameMean(Integrator::Path, 2, 512); }

/// Root mean square difference of two images' green channels.
double rmse(const FrameView& a, const std::vector<glm::vec3>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < b.size(); ++i) sum += (a.radiance[i].g - b[i].g) * (a.radiance[i].g - b[i].g);
  return std::sqrt(sum / static_cast<double>(b.size()));
}

TEST(Restir, OneFrameIsCloserToTheMeanThanOneLightSample) {
  Renderer plain({2});
  buildManyLights(plain);
  const FrameView f = plain.render(narrowCamera(), settingsFor(Integrator::Direct, kSize, 1024));
  const std::vector<glm::vec3> reference(f.radiance.begin(), f.radiance.end());
  RenderSettings s = settingsFor(Integrator::Direct, kSize, 1);
  s.accumulate = false;
  // Without the lamp visibility map (RendererConfig::lampVisibility), one light sample chooses
  // lamps behind the walls as often as any; with it, fewer: resampling still gains, less.
  // The lamps' weights hold the cosine toward each lamp, so one light sample is already good
  // without the map too: resampling's error is about 0.59x of it here.
  for (const bool lampVisibility : {false, true}) {
    double plainError = 0.0, restirError = 0.0;
    for (bool restir : {false, true}) {
      Renderer r(RendererConfig{.threads = 2, .lampVisibility = lampVisibility});
      buildManyLights(r);
      s.restir = restir;
      FrameView frame;
      for (uint32_t i = 0; i < 6; ++i) {   // a still view, a new seed every frame as in play
        s.seed = 77 + i;
        frame = r.render(narrowCamera(), s);
      }
      (restir ? restirError : plainError) = rmse(frame, reference);
    }
    const std::string map = lampVisibility ? "_lamp_visibility" : "";
    RecordProperty("plain_rmse" + map, std::to_string(plainError));
    RecordProperty("restir_rmse" + map, std::to_string(restirError));
    EXPECT_LT(restirError, (lampVisibility ? 0.8 : 0.65) * plainError)
        << "lamp visibility " << lampVisibility << ": plain " << plainError << ", restir " << restirError;
  }
}

TEST(Restir, OneAndTwoThreadsGiveBitIdenticalImages) {
  std::vector<glm::vec3> images[2];
  for (uint32_t threads : {1u, 2u}) {
    Renderer r({threads});
    buildManyLights(r);
    RenderSettings s = settingsFor(Integrator::Path, kSize, 1, 2);
    s.restir = true;
    s.accumulate = false;
    FrameView f;
    for (uint32_t i = 0; i < 3; ++i) {   // a moving camera: history reprojected
      s.seed = i;
      f = r.render(lookAt({0.2f * i, -13, 11}, {0, -1, 0}, 60.0f), s);
    }
    images[threads - 1].assign(f.radiance.begin(), f.radiance.end());
  }
  ASSERT_EQ(images[0].size(), images[1].size());
  EXPECT_EQ(std::memcmp(images[0].data(), images[1].data(), images[0].size() * sizeof(glm::vec3)), 0);
}

}  // namespace
}  // namespace pa
