#include "port/engine_glue/sky_cube.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec4.hpp>

#include "port/q3formats/shader/material.h"   // uvTransformAt, skyFaceImage
#include "renderer/core/srgb.h"
#include "renderer/scene/lights/sky.h"      // cubeFaceBasis, cubeLookup: the layout of SkyDesc::faces

namespace glue {
namespace {

constexpr float kSkyRadius = 4096.0f;        // tr_sky.c radiusWorld
constexpr float kDefaultCloudHeight = 512.0f; // skyParms cloud height 0 means this
constexpr int kBottomFace = 5;

/// Which far-box image a direction shows and where (u right, v down, in [0, 1]): the cube face
/// of the direction in q3::SkyBox layout (the same as pa's), the image turned where stock turns it.
struct BoxLookup {
  int face = 0;
  glm::vec2 uv{0.0f};
};
BoxLookup stockBoxLookup(const glm::vec3& d) {
  const pa::CubeLookup where = pa::cubeLookup(d);
  const int face = static_cast<int>(where.face);
  glm::vec2 uv(where.u, where.v);
  if (q3::skyFaceImage(face).turned180) uv = glm::vec2(1.0f) - uv;
  return {face, uv};
}

/// Bilinear RGBA in [0, 1] at texture coordinates (s, t), repeating or clamped.
glm::vec4 sampleImage(const Image& image, glm::vec2 st, bool clamp) {
  const int w = image.width, h = image.height;
  float x = st.x * float(w) - 0.5f, y = st.y * float(h) - 0.5f;
  if (!std::isfinite(x) || !std::isfinite(y)) x = y = 0.0f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float ax = x - fx, ay = y - fy;
  // The two texel indices along an axis of n texels: i and i + 1, clamped or wrapped (one
  // division per axis; the second index wraps by comparison).
  auto pair = [clamp](long i, int n) -> std::array<int, 2> {
    if (clamp)
      return {static_cast<int>(std::clamp<long>(i, 0, n - 1)), static_cast<int>(std::clamp<long>(i + 1, 0, n - 1))};
    const long m = i % n;
    const int first = static_cast<int>(m < 0 ? m + n : m);
    return {first, first + 1 == n ? 0 : first + 1};
  };
  const auto [x0, x1] = pair(static_cast<long>(std::clamp(fx, -1e9f, 1e9f)), w);
  const auto [y0, y1] = pair(static_cast<long>(std::clamp(fy, -1e9f, 1e9f)), h);
  auto texel = [&](int px, int py) {
    const uint8_t* p = &image.rgba[(size_t(py) * w + px) * 4];
    return glm::vec4(p[0], p[1], p[2], p[3]) * (1.0f / 255.0f);
  };
  return (texel(x0, y0) * (1 - ax) + texel(x1, y0) * ax) * (1 - ay) +
         (texel(x0, y1) * (1 - ax) + texel(x1, y1) * ax) * ay;
}

glm::vec3 blendFactor(q3::BlendFactor f, const glm::vec4& src, const glm::vec3& dst) {
  switch (f) {
    case q3::BlendFactor::Zero: return glm::vec3(0.0f);
    case q3::BlendFactor::One: return glm::vec3(1.0f);
    case q3::BlendFactor::SrcColor: return glm::vec3(src);
    case q3::BlendFactor::OneMinusSrcColor: return glm::vec3(1.0f) - glm::vec3(src);
    case q3::BlendFactor::DstColor: return dst;
    case q3::BlendFactor::OneMinusDstColor: return glm::vec3(1.0f) - dst;
    case q3::BlendFactor::SrcAlpha: return glm::vec3(src.a);
    case q3::BlendFactor::OneMinusSrcAlpha: return glm::vec3(1.0f - src.a);
    case q3::BlendFactor::DstAlpha: return glm::vec3(1.0f);        // the framebuffer's alpha is 1
    case q3::BlendFactor::OneMinusDstAlpha: return glm::vec3(0.0f);
    case q3::BlendFactor::SrcAlphaSaturate: return glm::vec3(0.0f);  // min(src alpha, 1 - dst alpha)
  }
  return glm::vec3(1.0f);
}

/// The stage's colour multiplier (rgbGen, alphaGen) at `seconds`; sky vertices are white.
glm::vec4 stageColor(const q3::ShaderStage& stage, double seconds) {
  glm::vec4 color(1.0f);
  if (stage.rgbGen == q3::RgbGen::Const)
    color = glm::vec4(stage.constColor[0], stage.constColor[1], stage.constColor[2], 1.0f);
  else if (stage.rgbGen == q3::RgbGen::Wave)
    color = glm::vec4(glm::vec3(std::clamp(stage.rgbWave.evaluate(seconds), 0.0f, 1.0f)), 1.0f);
  if (stage.alphaGen == q3::AlphaGen::Const) color.a = stage.constAlpha;
  else if (stage.alphaGen == q3::AlphaGen::Wave) color.a = std::clamp(stage.alphaWave.evaluate(seconds), 0.0f, 1.0f);
  return glm::clamp(color, 0.0f, 1.0f);
}

/// A colour channel in [0, 1] as a byte, rounded half away from zero (std::lround's result
/// without its call: the double sum of a float and 0.5 is exact).
uint8_t toByte(float c) { return static_cast<uint8_t>(double(std::clamp(c, 0.0f, 1.0f) * 255.0f) + 0.5); }

}  // namespace

glm::vec3 skyCubeDirection(int face, int x, int y, int size) {
  const pa::CubeFaceBasis& f = pa::cubeFaceBasis(static_cast<uint32_t>(std::clamp(face, 0, 5)));
  const float u = (float(x) + 0.5f) / float(size), v = (float(y) + 0.5f) / float(size);
  return f.axis + f.right * (2.0f * u - 1.0f) + f.top * (1.0f - 2.0f * v);
}

glm::vec2 cloudTexCoords(const glm::vec3& direction, float cloudHeight) {
  const float h = cloudHeight > 0.0f ? cloudHeight : kDefaultCloudHeight;
  const float r = kSkyRadius;
  const float lengthSquared = glm::dot(direction, direction);
  if (!(lengthSquared > 0.0f)) return glm::vec2(0.0f);
  // |p d + (0, 0, r)| = r + h, the positive root.
  const float b = direction.z * r;
  const float p = (-b + std::sqrt(b * b + lengthSquared * (2.0f * r * h + h * h))) / lengthSquared;
  glm::vec3 v = direction * p;
  v.z += r;
  v = glm::normalize(v);
  return {std::acos(std::clamp(v.x, -1.0f, 1.0f)), std::acos(std::clamp(v.y, -1.0f, 1.0f))};
}

bool SkyBaker::prepare(const q3::ShaderDef& shader, const SkyImageLoader& load, int size) {
  size_ = std::clamp(size, 8, 1024);
  layers_.clear();
  farBox_ = {};
  animated_ = false;
  bool anyFace = false;
  if (shader.sky && !shader.sky->farBox.empty()) {
    for (size_t i = 0; i < 6; ++i) {
      farBox_[i] = load(shader.sky->farBox + q3::skyFaceImage(int(i)).suffix);
      anyFace = anyFace || farBox_[i] != nullptr;
    }
  }
  for (const q3::ShaderStage& stage : shader.stages) {
    if (stage.source != q3::TextureSource::Image || stage.textures.empty()) continue;
    auto image = load(stage.textures.front());
    if (!image) continue;
    layers_.push_back({stage, std::move(image)});
    animated_ = animated_ || !stage.tcMods.empty() || stage.rgbGen == q3::RgbGen::Wave ||
                stage.alphaGen == q3::AlphaGen::Wave;
  }
  if (!anyFace && layers_.empty()) return false;
  boxColors_.assign(size_t(6) * size_ * size_, glm::vec3(0.0f));
  for (int face = 0; face < 6; ++face)
    for (int y = 0; y < size_; ++y)
      for (int x = 0; x < size_; ++x) {
        const BoxLookup where = stockBoxLookup(skyCubeDirection(face, x, y, size_));
        if (const Image* box = farBox_[size_t(where.face)].get())
          boxColors_[(size_t(face) * size_ + y) * size_ + x] = glm::vec3(sampleImage(*box, where.uv, true));
      }
  cloudHeight_ = shader.sky ? shader.sky->cloudHeight : kDefaultCloudHeight;
  cloudCoords_.assign(size_t(kBottomFace) * size_ * size_, glm::vec2(0.0f));
  for (int face = 0; face < kBottomFace; ++face)
    for (int y = 0; y < size_; ++y)
      for (int x = 0; x < size_; ++x)
        cloudCoords_[(size_t(face) * size_ + y) * size_ + x] =
            cloudTexCoords(skyCubeDirection(face, x, y, size_), cloudHeight_);
  return true;
}

SkyBaker::LayerState SkyBaker::layersAt(double seconds) const {
  LayerState state;
  layersAt(seconds, state);
  return state;
}

void SkyBaker::layersAt(double seconds, LayerState& state) const {
  state.transforms.clear();
  state.colors.clear();
  state.transforms.reserve(layers_.size());
  state.colors.reserve(layers_.size());
  for (const Layer& layer : layers_) {
    state.transforms.push_back(q3::uvTransformAt(layer.stage.tcMods, seconds));
    state.colors.push_back(stageColor(layer.stage, seconds));
  }
}

glm::vec3 SkyBaker::composeClouds(glm::vec3 color, glm::vec2 st, const LayerState& state) const {
  for (size_t l = 0; l < layers_.size(); ++l) {
    const Layer& layer = layers_[l];
    const auto uv = state.transforms[l].apply(st.x, st.y);
    const glm::vec4 src = sampleImage(*layer.image, {uv[0], uv[1]}, layer.stage.clamp) * state.colors[l];
    if (!layer.stage.blends()) {
      color = glm::vec3(src);
      continue;
    }
    color = glm::clamp(glm::vec3(src) * blendFactor(layer.stage.srcBlend, src, color) +
                           color * blendFactor(layer.stage.dstBlend, src, color),
                       0.0f, 1.0f);
  }
  return color;
}

glm::vec3 SkyBaker::colorAt(const glm::vec3& direction, const LayerState& state) const {
  const BoxLookup where = stockBoxLookup(direction);
  glm::vec3 color(0.0f);
  if (const Image* box = farBox_[size_t(where.face)].get()) color = glm::vec3(sampleImage(*box, where.uv, true));
  if (where.face == kBottomFace) return color;
  return composeClouds(color, cloudTexCoords(direction, cloudHeight_), state);
}

void SkyBaker::bake(double seconds, SkyCube& out) const {
  out.size = size_;
  const LayerState state = layersAt(seconds);
  for (auto& face : out.faces) face.resize(size_t(size_) * size_ * 4);
  auto bakeRow = [&](int face, int y) {
    uint8_t* p = &out.faces[size_t(face)][size_t(y) * size_ * 4];
    const size_t row = (size_t(face) * size_ + y) * size_;
    for (int x = 0; x < size_; ++x, p += 4) {
      glm::vec3 color = boxColors_[row + x];
      if (face != kBottomFace) color = composeClouds(color, cloudCoords_[row + x], state);
      p[0] = toByte(color.r);
      p[1] = toByte(color.g);
      p[2] = toByte(color.b);
      p[3] = 255;
    }
  };
  tbb::parallel_for(tbb::blocked_range<int>(0, 6 * size_, 16), [&](const tbb::blocked_range<int>& range) {
    for (int r = range.begin(); r < range.end(); ++r) bakeRow(r / size_, r % size_);
  });
}

StockSkyPicture::StockSkyPicture(std::shared_ptr<const SkyBaker> baker, double seconds)
    : baker_(std::move(baker)), state_(baker_->layersAt(seconds)) {}

glm::vec3 StockSkyPicture::radiance(const glm::vec3& dir) const {
  const glm::vec3 display = baker_->colorAt(dir, state_);
  return {pa::srgbToLinear(display.r), pa::srgbToLinear(display.g), pa::srgbToLinear(display.b)};
}

void StockSkyPicture::setTime(double seconds) { baker_->layersAt(seconds, state_); }

std::shared_ptr<StockSkyPicture> stockSkyPictureAt(std::shared_ptr<const SkyBaker> baker, double seconds) {
  if (!baker) return nullptr;
  return std::make_shared<StockSkyPicture>(std::move(baker), seconds);
}

glm::vec3 skyCubeMeanLinear(const SkyCube& cube) {
  glm::vec3 mean(0.0f);
  for (const std::vector<uint8_t>& face : cube.faces) {
    const size_t texels = face.size() / 4;
    if (texels == 0) continue;
    glm::dvec3 sum(0.0);
    for (size_t i = 0; i < texels; ++i)
      for (int c = 0; c < 3; ++c) sum[c] += pa::srgbToLinear(float(face[i * 4 + size_t(c)]) / 255.0f);
    mean += glm::vec3(sum / double(texels)) / 6.0f;
  }
  return mean;
}

pa::SkyDesc litStockSky(const pa::SkyDesc& stock, const glm::vec3& stockMean, const pa::SkyDesc& bridge,
                        const glm::vec3& lighting) {
  // The look's brightest channel lights as the compiled sky's brightest channel (q3map2 scales
  // its sky colour so; light recovery subtracts that light): a deep blue night sky brought to
  // the luminance of its white compiled light would light several times that light in blue.
  const glm::vec3 look = stockMean * stock.color * stock.intensity;
  const float shown = std::max({look.r, look.g, look.b});
  const float lit = std::max({lighting.r, lighting.g, lighting.b});
  if (!(shown > 1e-6f) && lit > 0.0f) return bridge;   // a black stock look cannot carry the light
  pa::SkyDesc sky = stock;
  sky.lightingScale = lit > 0.0f ? lit / shown : 0.0f;
  sky.ambientRadiance = bridge.ambientRadiance;
  sky.minimumRadiance = bridge.minimumRadiance;
  return sky;
}

}  // namespace glue
