// The per-pixel expectation does not depend on the samples per pixel (an emissive quad must not
// read darker at 1 spp than at 128 spp). Known answers: an emitter filling the view is
// exactly its radiance Le in every sample of every integrator, spp, frame count, denoised or
// not, with or without other lights (light tree, MIS) in the scene. Statistics: a floor lit by
// an emissive quad has the same mean at 1 spp (over many seeds) as at 256 spp, within 5
// standard errors computed from the sample variances. Film: the running mean over frames is the
// mean of the frames' own samples, traced one by one through traceSample. The emission AOV (what
// the denoiser leaves unfiltered) is the emitter's Le seen directly and nothing else.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "renderer/scene/film/film.h"
#include "renderer/scene/integrator/camera_rays.h"
#include "renderer/scene/integrator/integrator.h"
#include "renderer/scene/sampling/sobol_sampler.h"
#include "renderer/scene/world/scene_store.h"
#include "scene_builders.h"

namespace pa {
namespace {

using test::lookAt;
using test::settingsFor;

/// Adds one mesh with a material of its own to a Renderer or a SceneStore.
template <typename Target>
void addMesh(Target& target, const test::MeshArrays& mesh, const MaterialDesc& material) {
  test::addMesh(target, mesh, target.addMaterial(material));
}

MaterialDesc emitter(const glm::vec3& radiance, float albedo) {
  MaterialDesc m = test::diffuse(albedo);
  m.emission = radiance;
  m.twoSided = false;
  return m;
}

/// A one-sided emissive quad at z = 0 facing +z, far wider than the view of cameraAbove().
/// With `crowded`, a point light and 8 emissive quads lie behind it (below, facing up): the
/// light tree and MIS have work to do, yet nothing can light the quad's front, so every camera
/// sample must return exactly Le.
void buildEmitterFillingTheView(Renderer& r, const glm::vec3& radiance, float albedo, bool crowded) {
  addMesh(r, test::quad({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}), emitter(radiance, albedo));
  if (crowded) {
    for (int i = 0; i < 8; ++i) {
      const float x = -4.0f + static_cast<float>(i);
      addMesh(r, test::quad({x, -0.5f, -2.0f - 0.1f * i}, {0.5f, 0, 0}, {0, 1, 0}), emitter(glm::vec3(5.0f), 0.5f));
    }
    LightDesc point;
    point.position = {0, 0, -3};
    point.intensity = 10.0f;
    r.addLight(point);
  }
  r.commit();
}

Camera cameraAbove() { return lookAt({0, 0, 2}, {0, 0, 0}, 30.0f); }

void expectEveryPixelIs(const FrameView& f, const glm::vec3& expected, const char* what) {
  ASSERT_EQ(f.radiance.size(), size_t{f.width} * f.height);
  for (size_t i = 0; i < f.radiance.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(f.radiance[i][c], expected[c], 1e-5f * expected[c]) << what << ", pixel " << i << ", channel " << c;
    }
  }
}

TEST(EmissionExpectation, EmitterFillingTheViewIsExactlyLeInEveryTracedIntegrator) {
  const glm::vec3 le(3.0f, 2.0f, 0.5f);
  for (bool crowded : {false, true}) {
    for (Integrator integrator : {Integrator::Direct, Integrator::Path}) {
      for (uint32_t spp : {1u, 16u}) {
        for (bool denoise : {false, true}) {
          Renderer r({2});
          buildEmitterFillingTheView(r, le, 0.5f, crowded);
          RenderSettings s = settingsFor(integrator, 12, spp, integrator == Integrator::Path ? 4 : 1);
          s.denoise = denoise;
          const std::string what = std::string(integrator == Integrator::Path ? "path" : "direct") +
                                   (crowded ? " crowded" : " alone") + ", spp " + std::to_string(spp) +
                                   (denoise ? ", denoised" : "");
          expectEveryPixelIs(r.render(cameraAbove(), s), le, (what + ", frame 1").c_str());
          // Accumulated frames use other sample indices: still exactly Le.
          for (int frame = 2; frame <= 3; ++frame) r.render(cameraAbove(), s);
          expectEveryPixelIs(r.render(cameraAbove(), s), le, (what + ", frame 4").c_str());
        }
      }
    }
  }
}

TEST(EmissionExpectation, EmitterFillingTheViewIsExactlyLeInTheLightmapIntegrator) {
  // Lightmap composes emission over base colour x fullbright in display values, clamped to 1:
  // a black base colour and Le <= 1 leave exactly Le (through an sRGB round trip).
  const glm::vec3 le(0.8f, 0.5f, 0.25f);
  for (uint32_t spp : {1u, 16u}) {
    for (bool denoise : {false, true}) {
      Renderer r({2});
      buildEmitterFillingTheView(r, le, 0.0f, true);
      RenderSettings s = settingsFor(Integrator::Lightmap, 12, spp);
      s.denoise = denoise;
      expectEveryPixelIs(r.render(cameraAbove(), s), le, denoise ? "lightmap, denoised" : "lightmap");
    }
  }
}

/// A grey floor (albedo 0.5) lit by a 1 x 1 grey emissive quad 2 above it, facing down, out of view.
template <typename Target>
void buildLitFloor(Target& target) {
  addMesh(target, test::quad({-20, -20, 0}, {40, 0, 0}, {0, 40, 0}), test::diffuse(0.5f));
  addMesh(target, test::quad({-0.5f, -0.5f, 2}, {0, 1, 0}, {1, 0, 0}), emitter(glm::vec3(4.0f), 0.5f));
}

Camera cameraOnFloor() { return lookAt({3, 0, 1.5f}, {0, 0, 0}, 40.0f); }

/// Per-pixel running statistics of the grey radiance over many images.
std::vector<RunningStats> perPixelStats(Integrator integrator, uint32_t bounces, uint32_t size, uint32_t seeds) {
  std::vector<RunningStats> stats(size_t{size} * size);
  Renderer r({2});
  buildLitFloor(r);
  r.commit();
  RenderSettings s = settingsFor(integrator, size, 1, bounces);
  for (uint32_t seed = 0; seed < seeds; ++seed) {
    s.seed = 1000 + seed;   // a new seed restarts the film: every image is one sample, index 0
    const FrameView f = r.render(cameraOnFloor(), s);
    EXPECT_EQ(f.accumulatedFrames, 1u);
    for (size_t i = 0; i < stats.size(); ++i) stats[i].add(f.radiance[i].g);
  }
  return stats;
}

void expectSameExpectationAtOneAndManySpp(Integrator integrator, uint32_t bounces) {
  constexpr uint32_t kSize = 8, kSeeds = 512, kReferenceSpp = 256;
  const std::vector<RunningStats> one = perPixelStats(integrator, bounces, kSize, kSeeds);
  Renderer r({2});
  buildLitFloor(r);
  r.commit();
  const FrameView many = r.render(cameraOnFloor(), settingsFor(integrator, kSize, kReferenceSpp, bounces));
  double sumOne = 0.0, sumMany = 0.0, varianceOfSums = 0.0;
  for (size_t i = 0; i < one.size(); ++i) {
    // Grey radiance: luminance (whose variance the film keeps) equals the green channel.
    const double variance = one[i].varianceOfMean() + many.variance[i];
    const double difference = one[i].mean() - many.radiance[i].g;
    EXPECT_LE(std::abs(difference), 5.0 * std::sqrt(variance) + 1e-6) << "pixel " << i << ": 1 spp mean "
                                                                        << one[i].mean() << ", " << kReferenceSpp
                                                                        << " spp " << many.radiance[i].g;
    sumOne += one[i].mean();
    sumMany += many.radiance[i].g;
    varianceOfSums += variance;
  }
  EXPECT_GT(sumMany, 0.0);
  EXPECT_LE(std::abs(sumOne - sumMany), 4.0 * std::sqrt(varianceOfSums))
      << "image means " << sumOne / one.size() << " (1 spp) and " << sumMany / one.size() << " (256 spp)";
}

TEST(EmissionExpectation, LitFloorHasTheSameMeanAtOneAndManySppDirect) {
  expectSameExpectationAtOneAndManySpp(Integrator::Direct, 1);
}

TEST(EmissionExpectation, LitFloorHasTheSameMeanAtOneAndManySppPath) {
  expectSameExpectationAtOneAndManySpp(Integrator::Path, 3);
}

TEST(EmissionExpectation, RunningMeanOverFramesIsTheMeanOfTheFramesOwnSamples) {
  // Frame f of a 1-spp accumulation traces sample index f of each pixel (see renderer.cpp):
  // the film's mean after F frames must be the plain mean of those F samples, traced here one
  // by one, and likewise after every shorter prefix.
  constexpr uint32_t kSize = 6, kFrames = 48, kSeed = 5;
  RenderSettings settings = settingsFor(Integrator::Path, kSize, 1, 3);
  settings.seed = kSeed;
  SceneStore store;
  buildLitFloor(store);
  const RenderScene scene = store.commit();
  const CameraRays rays(cameraOnFloor(), kSize, kSize);
  std::vector<std::vector<double>> sums(kSize * kSize, std::vector<double>(3, 0.0));

  Renderer r({2});
  buildLitFloor(r);
  r.commit();
  for (uint32_t frame = 0; frame < kFrames; ++frame) {
    const FrameView f = r.render(cameraOnFloor(), settings);
    ASSERT_EQ(f.accumulatedFrames, frame + 1);
    for (uint32_t y = 0; y < kSize; ++y) {
      for (uint32_t x = 0; x < kSize; ++x) {
        const uint32_t pixel = y * kSize + x;
        const sampling::PixelSampler sampler(sampling::hashCombine(sampling::hash32(kSeed), pixel), frame);
        const glm::vec4 jitter = sampler.get4(0);
        const PixelSample sample = traceSample(scene, rays, settings, static_cast<float>(x) + jitter.x,
                                               static_cast<float>(y) + jitter.y, sampler);
        for (int c = 0; c < 3; ++c) {
          sums[pixel][c] += sample.radiance[c];
          const double mean = sums[pixel][c] / (frame + 1);
          ASSERT_NEAR(f.radiance[pixel][c], mean, 1e-6 * std::max(1.0, mean))
              << "frame " << frame << ", pixel " << pixel << ", channel " << c;
        }
      }
    }
  }
}

TEST(EmissionExpectation, EmissionAovIsWhatTheCameraSeesBeforeAnyScattering) {
  // PixelSample::emission is the part of radiance the denoiser leaves alone: an emitter's Le seen
  // directly (its reflected light is not part of it), nothing on a lit floor.
  SceneStore store;
  buildLitFloor(store);
  const RenderScene scene = store.commit();
  const RenderSettings settings = settingsFor(Integrator::Path, 4, 1, 3);
  const auto trace = [&](const Camera& camera, uint32_t index) {
    const CameraRays rays(camera, 4, 4);
    const sampling::PixelSampler sampler(sampling::hash32(index), index);
    return traceSample(scene, rays, settings, 2.0f, 2.0f, sampler);
  };
  for (uint32_t i = 0; i < 64; ++i) {
    const PixelSample lamp = trace(lookAt({0, 0, 1}, {0, 0, 2}, 10.0f), i);   // from below, head-on
    EXPECT_EQ(lamp.emission, glm::vec3(4.0f)) << i;
    EXPECT_GE(lamp.radiance.g, 4.0f) << i;   // plus what the lamp reflects of the lit floor
    const PixelSample floor = trace(cameraOnFloor(), i);
    EXPECT_EQ(floor.emission, glm::vec3(0.0f)) << i;
  }
}

TEST(EmissionExpectation, FilmResolvesTheEmissionMean) {
  Film film;
  film.resize(1, 1);
  PixelSample sample;
  sample.radiance = glm::vec3(5.0f);
  sample.emission = glm::vec3(3.0f);
  film.pixel(0, 0).add(sample);
  sample.emission = glm::vec3(1.0f);
  film.pixel(0, 0).add(sample);
  sample.radiance.x = std::numeric_limits<float>::quiet_NaN();   // a broken path counts as black, all of it
  film.pixel(0, 0).add(sample);
  film.finishFrame();
  film.resolveMeanRows(0, 1);
  EXPECT_FLOAT_EQ(film.emission()[0].g, 4.0f / 3.0f);
  EXPECT_FLOAT_EQ(film.radiance()[0].g, 10.0f / 3.0f);
}

/// An emitter whose look is authored apart from its light (MaterialDesc::seenEmission): camera
/// rays see the look exactly, directly and through a mirror, even where the light is 0.
TEST(EmissionExpectation, CameraRaysSeeTheSeenEmissionNotTheLight) {
  const glm::vec3 seen(0.8f, 0.6f, 0.2f);
  for (const glm::vec3 light : {glm::vec3(0.0f), glm::vec3(300.0f, 200.0f, 100.0f)}) {
    for (Integrator integrator : {Integrator::Direct, Integrator::Path}) {
      Renderer r({2});
      MaterialDesc m = emitter(light, 0.0f);
      m.seenEmission = seen;
      addMesh(r, test::quad({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}), m);
      r.commit();
      const RenderSettings s = settingsFor(integrator, 12, 4, integrator == Integrator::Path ? 4 : 1);
      expectEveryPixelIs(r.render(cameraAbove(), s), seen, light.x > 0.0f ? "seen, bright light" : "seen, no light");
    }
  }
  // Through a mirror filling the view (facing down at z = 1), the camera below looks up at it
  // and sees the emitter beneath itself (z = -1, facing up).
  Renderer r({2});
  MaterialDesc mirror = test::diffuse(1.0f);
  mirror.mirror = true;
  addMesh(r, test::quad({-50, -50, 1}, {0, 100, 0}, {100, 0, 0}), mirror);
  MaterialDesc m = emitter(glm::vec3(50.0f), 0.0f);
  m.seenEmission = seen;
  addMesh(r, test::quad({-50, -50, -1}, {100, 0, 0}, {0, 100, 0}), m);
  r.commit();
  const FrameView f = r.render(lookAt({0, 0, 0}, {0, 0, 1}, 30.0f), settingsFor(Integrator::Path, 12, 2, 4));
  expectEveryPixelIs(f, seen, "seen through a mirror");
}

/// The light an emitter gives does not depend on its seen look: a floor lit by an emitter out of
/// view is the same image, bit for bit, whatever the emitter's seenEmission.
TEST(EmissionExpectation, SeenEmissionLeavesTheLightUnchanged) {
  for (Integrator integrator : {Integrator::Direct, Integrator::Path}) {
    std::vector<glm::vec3> images[2];
    for (int apart = 0; apart < 2; ++apart) {
      Renderer r({2});
      addMesh(r, test::quad({-20, -20, 0}, {40, 0, 0}, {0, 40, 0}), test::diffuse(0.5f));
      MaterialDesc lamp = emitter(glm::vec3(4.0f), 0.5f);
      if (apart) lamp.seenEmission = glm::vec3(0.1f);
      addMesh(r, test::quad({-0.5f, -0.5f, 2}, {0, 1, 0}, {1, 0, 0}), lamp);
      r.commit();
      const FrameView f = r.render(cameraOnFloor(), settingsFor(integrator, 16, 8, 4));
      images[apart].assign(f.radiance.begin(), f.radiance.end());
    }
    ASSERT_EQ(images[0].size(), images[1].size());
    float peak = 0.0f;
    for (size_t i = 0; i < images[0].size(); ++i) {
      ASSERT_EQ(images[0][i], images[1][i]) << "pixel " << i;
      peak = std::max(peak, images[0][i].g);
    }
    EXPECT_GT(peak, 0.01f) << "the floor is lit";
  }
}

}  // namespace
}  // namespace pa
