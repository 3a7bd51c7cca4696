#include "renderer/scene/taau/taau.h"

#include "renderer/scene/taau/lanes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/geometric.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace pa::taau {
namespace {

constexpr uint32_t kRowGrain = 8;        // rows per parallel task

float halton(uint32_t index, uint32_t base) {
  float f = 1.0f, r = 0.0f;
  for (uint32_t i = index; i > 0; i /= base) {
    f /= static_cast<float>(base);
    r += f * static_cast<float>(i % base);
  }
  return r;
}

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

float linearToSrgb(float c) { return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f; }

glm::vec3 toYCoCg(const glm::vec3& c) {
  return {0.25f * c.r + 0.5f * c.g + 0.25f * c.b, 0.5f * c.r - 0.5f * c.b, -0.25f * c.r + 0.5f * c.g - 0.25f * c.b};
}

namespace L = lanes;
using L::F;
using L::I;

/// Catmull-Rom weights of the four taps around positions t in [0, 1) past the second one.
std::array<F, 4> catmullRom(F t) {
  const F t2 = t * t;
  return {t * (-0.5f + t * (1.0f - 0.5f * t)), 1.0f + t2 * (-2.5f + 1.5f * t), t * (0.5f + t * (2.0f - 1.5f * t)),
          t2 * (-0.5f + 0.5f * t)};
}

/// Reads the lanes at per-lane indices from planes of one layout: one load where the indices are
/// consecutive, one or two loads and a permutation where they lie within kCount or 2 kCount values
/// from the first lane's (every plane has kPad >= 2 kCount readable values past its end), one
/// read per lane otherwise.
class Fetch {
 public:
  enum class Kind : uint8_t { Gather, Window, NarrowWindow, Consecutive };
  /// How lanes at `offset` from one index are read.
  static Kind kind(I offset) {
    if (L::all(offset == L::kIota)) return Kind::Consecutive;
    if (L::any((offset < 0) | (offset >= 2 * L::kCount))) return Kind::Gather;
    return L::all(offset < L::kCount) ? Kind::NarrowWindow : Kind::Window;
  }
  explicit Fetch(I index) : base_(index[0]), offset_(index - index[0]), kind_(kind(offset_)) {}
  Fetch() : base_(0), offset_(L::kIota), kind_(Kind::Consecutive) {}

  F operator()(const std::vector<float>& plane) const { return read(plane.data() + base_, offset_, kind_); }
  I operator()(const std::vector<int32_t>& plane) const { return read(plane.data() + base_, offset_, kind_); }

  /// Per lane, p[offset] read as `kind` says.
  template <class T>
  static auto read(const T* p, I offset, Kind kind) -> decltype(L::load(p)) {
    switch (kind) {
      case Kind::Consecutive: return L::load(p);
      case Kind::NarrowWindow: return L::permute1(p, offset);
      case Kind::Window: return L::permute(p, offset);
      default: return L::gather(p, offset);
    }
  }

 private:
  int base_;
  I offset_;
  Kind kind_;
};

/// Reads the lanes at columns x, rows y of planes `stride` values a row, and at any fixed offset
/// (dx, dy) from those, with one load where the columns are consecutive on one row, one or two
/// loads and a permutation where they lie within kCount or 2 kCount columns of the leftmost, on
/// one row or on two consecutive rows (twice that and a select), one read per lane otherwise. The
/// pixels at the offsets read must lie in the plane.
class GridFetch {
 public:
  GridFetch(I x, I y, int stride) : stride_(stride) {
    if (L::all((y == y[0]) & (x == x[0] + L::kIota))) {   // the usual case, first
      base_ = y[0] * stride + x[0];
      offset_ = L::kIota;
      lower_ = L::splat(0);
      kind_ = Fetch::Kind::Consecutive;
      return;
    }
    int left = x[0], top = y[0];
    for (int l = 1; l < L::kCount; ++l) {
      left = std::min(left, x[l]);
      top = std::min(top, y[l]);
    }
    base_ = top * stride + left;
    offset_ = x - left;
    lower_ = y != top;
    twoRows_ = L::any(lower_);
    kind_ = Fetch::kind(offset_);
    if (twoRows_ && kind_ == Fetch::Kind::Consecutive) kind_ = Fetch::Kind::NarrowWindow;   // offsets 0 .. kCount - 1
    if (L::any(y - top > 1)) kind_ = Fetch::Kind::Gather;
    if (kind_ == Fetch::Kind::Gather) {
      offset_ = (y - top) * stride + offset_;
      twoRows_ = false;
    }
  }
  /// How the lanes are read (Consecutive: one load at `first()`).
  Fetch::Kind kind() const { return kind_; }
  /// Index of the top-left pixel read.
  int first() const { return base_; }

  /// Per lane, plane[(y + dy) * stride + x + dx].
  template <class T>
  auto operator()(const std::vector<T>& plane, int dy, int dx) const -> decltype(L::load(plane.data())) {
    const T* p = plane.data() + base_ + dy * stride_ + dx;
    const auto v = Fetch::read(p, offset_, kind_);
    return twoRows_ ? L::select(lower_, Fetch::read(p + stride_, offset_, kind_), v) : v;
  }

 private:
  int stride_, base_ = 0;
  I offset_, lower_;
  bool twoRows_ = false;
  Fetch::Kind kind_ = Fetch::Kind::Gather;
};

template <class Body>
void parallelRows(uint32_t height, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, height, kRowGrain),
                    [&](const tbb::blocked_range<uint32_t>& r) { body(r.begin(), r.end()); });
}

}  // namespace

glm::vec2 jitter(uint32_t frame) {
  const uint32_t i = frame % kJitterPeriod + 1;   // Halton index 0 is (0, 0): skip it
  return {halton(i, 2) - 0.5f, halton(i, 3) - 0.5f};
}

Upscaler::Upscaler(const Config& config) : config_(config) {
  for (uint32_t i = 0; i < 256; ++i) decode_[i] = srgbToLinear(static_cast<float>(i) / 255.0f);
  for (uint32_t i = 0; i < kEncodeSteps; ++i) {
    const float s = static_cast<float>(i) / static_cast<float>(kEncodeSteps - 1);
    encode_[i] = static_cast<uint8_t>(std::lround(std::clamp(linearToSrgb(s * s), 0.0f, 1.0f) * 255.0f));
  }
}

void Upscaler::reset() { haveHistory_ = false; }

std::span<const uint8_t> Upscaler::resolve(const Frame& frame, uint32_t outWidth, uint32_t outHeight) {
  const size_t traced = size_t{frame.width} * frame.height;
  if (outWidth == 0 || outHeight == 0 || traced == 0 || frame.rgba8.size() != traced * 4 ||
      frame.motion.size() != traced || frame.depth.size() != traced || frame.instance.size() != traced)
    return {};
  const size_t n = size_t{outWidth} * outHeight;
  if (outWidth != outWidth_ || outHeight != outHeight_) {
    outWidth_ = outWidth;
    outHeight_ = outHeight;
    paddedWidth_ = (outWidth + L::kCount - 1) / L::kCount * L::kCount;
    haveHistory_ = false;
    history_.assign(n);
    nextHistory_.assign(n);
    weight_.assign(n + kPad, 0.0f);
    nextWeight_.assign(n + kPad, 0.0f);
    instance_.assign(n + kPad, static_cast<int32_t>(kNoId));
    nextInstance_.assign(n + kPad, static_cast<int32_t>(kNoId));
    boxLo_.assign(n);
    boxHi_.assign(n);
    nextBoxLo_.assign(n);
    nextBoxHi_.assign(n);
    output_.assign(n * 4, 255);
    lastCamera_.reset();
  }
  if (samples_.y.size() != traced + kPad) {
    samples_.assign(traced);
    mean_.assign(traced);
    sigma_.assign(traced);
    closestDepth_.assign(traced + kPad, 0.0f);
    closestMotionX_.assign(traced + kPad, 0.0f);
    closestMotionY_.assign(traced + kPad, 0.0f);
    closestInstance_.assign(traced + kPad, 0);
  }
  rays_.reset();
  previousRays_.reset();
  if (frame.camera != nullptr) {
    rays_.emplace(*frame.camera, outWidth, outHeight);
    if (lastCamera_) previousRays_.emplace(*lastCamera_, outWidth, outHeight);
  }
  weightCap_ = historyWeightCap(config_, static_cast<float>(traced) / static_cast<float>(n));
  kernelTaps(frame.width, outWidth, frame.jitter.x, config_.kernelRadius, columns_, columnD2_);
  kernelTaps(frame.height, outHeight, frame.jitter.y, config_.kernelRadius, rows_, rowD2_);
  movingRadius_ = movingKernelRadius(config_, frame.width, frame.height, outWidth, outHeight);
  kernelTaps(frame.width, outWidth, frame.jitter.x, movingRadius_, movingColumns_, movingColumnD2_);
  kernelTaps(frame.height, outHeight, frame.jitter.y, movingRadius_, movingRows_, movingRowD2_);
  laneTaps(frame.width, columns_, columnD2_, laneColumns_);
  laneTaps(frame.width, movingColumns_, movingColumnD2_, movingLaneColumns_);
  nearestColumn_.resize(paddedWidth_);
  for (uint32_t x = 0; x < paddedWidth_; ++x) nearestColumn_[x] = columns_[std::min(x, outWidth - 1)].nearest;
  parallelRows(frame.height, [&](uint32_t y0, uint32_t y1) { prepareRows(frame, y0, y1); });
  parallelRows(frame.height, [&](uint32_t y0, uint32_t y1) { neighbourhoodRows(frame, y0, y1); });
  parallelRows(outHeight, [&](uint32_t y0, uint32_t y1) { resolveRows(frame, y0, y1); });
  history_.swap(nextHistory_);
  std::swap(weight_, nextWeight_);
  std::swap(instance_, nextInstance_);
  boxLo_.swap(nextBoxLo_);
  boxHi_.swap(nextBoxHi_);
  haveHistory_ = true;
  if (frame.camera != nullptr) lastCamera_ = *frame.camera;
  else lastCamera_.reset();
  return output_;
}

float movingKernelRadius(const Config& config, uint32_t tracedWidth, uint32_t tracedHeight, uint32_t outWidth,
                         uint32_t outHeight) {
  const float across = static_cast<float>(outWidth) / static_cast<float>(std::max(tracedWidth, 1u));
  const float down = static_cast<float>(outHeight) / static_cast<float>(std::max(tracedHeight, 1u));
  const float outputPerTraced = std::max(across, down);
  return std::max(config.movingKernelRadius, config.movingKernelReach * outputPerTraced);
}

float historyWeightCap(const Config& config, float samplesPerPixel) {
  return config.memoryFrames * 3.14159265f * config.kernelRadius * config.kernelRadius / 3.0f * samplesPerPixel;
}

void kernelTaps(uint32_t traced, uint32_t out, float jitter, float radius, std::vector<AxisTaps>& taps,
                std::vector<float>& d2) {
  const float scale = static_cast<float>(traced) / static_cast<float>(out);   // traced pixels per output pixel
  const float inverse = 1.0f / scale;
  const float reach = radius * scale;   // in traced pixels
  taps.resize(out);
  d2.clear();   // memory kept between frames
  for (uint32_t o = 0; o < out; ++o) {
    AxisTaps& t = taps[o];
    const float q = (static_cast<float>(o) + 0.5f) * scale;   // the output pixel's centre in traced pixels
    t.nearest = std::clamp(static_cast<int>(std::floor(q - jitter)), 0, int(traced) - 1);
    t.first = std::max(0, static_cast<int>(std::ceil(q - jitter - 0.5f - reach)));
    const int last = std::min(int(traced) - 1, static_cast<int>(std::floor(q - jitter - 0.5f + reach)));
    t.count = std::max(0, last - t.first + 1);
    t.offset = static_cast<uint32_t>(d2.size());
    for (int i = t.first; i <= last; ++i) {
      const float d = (static_cast<float>(i) + 0.5f + jitter - q) * inverse;
      d2.push_back(d * d);
    }
  }
}

void Upscaler::laneTaps(uint32_t traced, const std::vector<AxisTaps>& taps, const std::vector<float>& d2,
                        LaneTaps& lanes) const {
  const uint32_t P = paddedWidth_;
  const int lastColumn = static_cast<int>(traced) - 1;
  lanes.count = 0;
  for (const AxisTaps& t : taps) lanes.count = std::max(lanes.count, t.count);
  const size_t lanesTaps = size_t(lanes.count) * P;
  lanes.offset.assign(lanesTaps, 0);
  lanes.d2.assign(lanesTaps, 1e30f);   // beyond the kernel: weight 0
  lanes.base.assign(P / L::kCount, 0);
  lanes.kind.assign(P / L::kCount, 0);
  for (uint32_t block = 0; block < P / L::kCount; ++block) {
    const uint32_t x0 = block * L::kCount;
    const int base = std::min(taps[x0].first, lastColumn);   // taps' first columns grow with x
    int reach = 0;
    for (uint32_t l = 0; l < L::kCount; ++l) {
      const AxisTaps& t = taps[std::min<uint32_t>(x0 + l, outWidth_ - 1)];   // past the row's end: its last column
      for (int b = 0; b < lanes.count; ++b) {
        const size_t at = size_t(b) * P + x0 + l;
        lanes.offset[at] = std::min(t.first + b, lastColumn) - base;
        reach = std::max(reach, lanes.offset[at]);
        if (b < t.count) lanes.d2[at] = d2[t.offset + uint32_t(b)];
      }
    }
    lanes.base[block] = base;
    lanes.kind[block] = static_cast<uint8_t>(reach < L::kCount ? Fetch::Kind::NarrowWindow
                                             : reach < 2 * L::kCount ? Fetch::Kind::Window : Fetch::Kind::Gather);
  }
}

void Upscaler::prepareRows(const Frame& frame, uint32_t y0, uint32_t y1) {
  for (size_t i = size_t{y0} * frame.width; i < size_t{y1} * frame.width; ++i) {
    const uint8_t* p = &frame.rgba8[i * 4];
    const glm::vec3 c = toYCoCg({decode_[p[0]], decode_[p[1]], decode_[p[2]]});
    samples_.y[i] = c.x;
    samples_.co[i] = c.y;
    samples_.cg[i] = c.z;
  }
}

void Upscaler::neighbourhoodRows(const Frame& frame, uint32_t y0, uint32_t y1) {
  const int w = static_cast<int>(frame.width), h = static_cast<int>(frame.height);
  const float* depth = frame.depth.data();
  // The neighbourhood of (x, y) from the 3 x 3 traced pixels around it that lie in the frame.
  const auto write = [&](int y, int x, int xa, int xb, int ya, int yb) {
    glm::vec3 m1(0.0f), m2(0.0f);
    float closestDepth = std::numeric_limits<float>::infinity();
    size_t closest = size_t(y) * size_t(w) + size_t(x);
    int count = 0;
    for (int iy = ya; iy <= yb; ++iy) {
      for (int ix = xa; ix <= xb; ++ix) {
        const size_t i = size_t(iy) * size_t(w) + size_t(ix);
        const glm::vec3 c(samples_.y[i], samples_.co[i], samples_.cg[i]);
        m1 += c;
        m2 += c * c;
        ++count;
        if (depth[i] < closestDepth) {
          closestDepth = depth[i];
          closest = i;
        }
      }
    }
    const float inv = 1.0f / static_cast<float>(count);
    const glm::vec3 mean = m1 * inv;
    const glm::vec3 sigma = glm::sqrt(glm::max(m2 * inv - mean * mean, glm::vec3(0.0f)));
    const size_t at = size_t(y) * size_t(w) + size_t(x);
    mean_.y[at] = mean.x;
    mean_.co[at] = mean.y;
    mean_.cg[at] = mean.z;
    sigma_.y[at] = sigma.x;
    sigma_.co[at] = sigma.y;
    sigma_.cg[at] = sigma.z;
    closestDepth_[at] = depth[closest];
    closestInstance_[at] = static_cast<int32_t>(frame.instance[closest]);
    closestMotionX_[at] = frame.motion[closest].x;
    closestMotionY_[at] = frame.motion[closest].y;
  };
  for (int y = static_cast<int>(y0); y < static_cast<int>(y1); ++y) {
    const int ya = std::max(y - 1, 0), yb = std::min(y + 1, h - 1);
    int x = 0;
    if (w >= 2) write(y, 0, 0, 1, ya, yb);
    else write(y, 0, 0, 0, ya, yb);
    // kCount pixels a step where all three columns of each lie in the frame: the same sums in the
    // same order as one pixel at a time.
    for (x = 1; x + L::kCount < w; x += L::kCount) {
      F m1y = L::splat(0.0f), m1co = m1y, m1cg = m1y, m2y = m1y, m2co = m1y, m2cg = m1y;
      F closestDepth = L::splat(std::numeric_limits<float>::infinity());
      I closest = L::splat(y * w + x) + L::kIota;
      for (int iy = ya; iy <= yb; ++iy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int i = iy * w + x + dx;
          const F cy = L::load(&samples_.y[size_t(i)]), cco = L::load(&samples_.co[size_t(i)]),
                  ccg = L::load(&samples_.cg[size_t(i)]);
          m1y += cy;
          m1co += cco;
          m1cg += ccg;
          m2y += cy * cy;
          m2co += cco * cco;
          m2cg += ccg * ccg;
          const F d = L::load(depth + i);
          const I closer = d < closestDepth;
          closestDepth = L::select(closer, d, closestDepth);
          closest = L::select(closer, L::splat(i) + L::kIota, closest);
        }
      }
      const float inv = 1.0f / static_cast<float>((yb - ya + 1) * 3);
      const size_t at = size_t(y) * size_t(w) + size_t(x);
      const auto moments = [&](F m1, F m2, std::vector<float>& mean, std::vector<float>& sigma) {
        const F mu = m1 * inv;
        L::store(&mean[at], mu);
        L::store(&sigma[at], L::sqrt(L::max(m2 * inv - mu * mu, L::splat(0.0f))));
      };
      moments(m1y, m2y, mean_.y, sigma_.y);
      moments(m1co, m2co, mean_.co, sigma_.co);
      moments(m1cg, m2cg, mean_.cg, sigma_.cg);
      for (int l = 0; l < L::kCount; ++l) {
        const size_t c = size_t(closest[l]);
        closestDepth_[at + size_t(l)] = depth[c];   // NaN or infinite all round: its own
        closestInstance_[at + size_t(l)] = static_cast<int32_t>(frame.instance[c]);
        closestMotionX_[at + size_t(l)] = frame.motion[c].x;
        closestMotionY_[at + size_t(l)] = frame.motion[c].y;
      }
    }
    for (; x < w; ++x) write(y, x, x - 1, std::min(x + 1, w - 1), ya, yb);
  }
}

void Upscaler::resolveRows(const Frame& frame, uint32_t y0, uint32_t y1) {
  const uint32_t w = frame.width, W = outWidth_, H = outHeight_, P = paddedWidth_;
  const float sx = static_cast<float>(w) / static_cast<float>(W);   // traced pixels per output pixel
  const float sy = static_cast<float>(frame.height) / static_cast<float>(H);
  const float invRadius2 = 1.0f / (config_.kernelRadius * config_.kernelRadius);
  const float invMovingRadius2 = 1.0f / (movingRadius_ * movingRadius_);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const I zero = L::splat(0), lastColumn = L::splat(int(W) - 1), lastRow = L::splat(int(H) - 1);
  const I lastTracedColumn = L::splat(int(w) - 1);
  // This frame's weighted sum of YCoCg and weight within one radius' kernel, kCount columns from x0.
  struct Sum {
    F y, co, cg, weight;
  };
  const auto kernel = [&](const LaneTaps& columns, const AxisTaps& row, const std::vector<float>& rowD2, float invR2,
                          uint32_t x0) {
    Sum s{L::splat(0.0f), L::splat(0.0f), L::splat(0.0f), L::splat(0.0f)};
    const int base = columns.base[x0 / L::kCount];
    const auto kind = static_cast<Fetch::Kind>(columns.kind[x0 / L::kCount]);
    for (int a = 0; a < row.count; ++a) {
      const float dy2 = rowD2[row.offset + uint32_t(a)];
      const size_t line = size_t(row.first + a) * w + size_t(base);
      for (int b = 0; b < columns.count; ++b) {
        const size_t at = size_t(b) * P + x0;
        const F u = (L::load(&columns.d2[at]) + dy2) * invR2;
        const F k = L::select(u < 1.0f, (1.0f - u) * (1.0f - u), L::splat(0.0f));
        const I offset = L::load(&columns.offset[at]);
        const auto tap = [&](const std::vector<float>& plane) { return Fetch::read(&plane[line], offset, kind); };
        s.y += k * tap(samples_.y);
        s.co += k * tap(samples_.co);
        s.cg += k * tap(samples_.cg);
        s.weight += k;
      }
    }
    return s;
  };
  const auto put = [&](auto& plane, size_t at, uint32_t active, auto v) {
    if (active == L::kCount) {
      L::store(&plane[at], v);
    } else {
      for (uint32_t l = 0; l < active; ++l) plane[at + l] = v[l];
    }
  };
  for (uint32_t oy = y0; oy < y1; ++oy) {
    const float cy = static_cast<float>(oy) + 0.5f;
    const float qy = cy * sy;   // the output pixels' centre row in traced pixels
    const int centreRow = rows_[oy].nearest * int(w);
    // Without history: this frame's row, interpolated bilinearly (as the stretch shows it).
    const float by = qy - frame.jitter.y - 0.5f;
    const int by0 = static_cast<int>(std::floor(by));
    const float bty = by - static_cast<float>(by0);
    const int bya = std::clamp(by0, 0, int(frame.height) - 1) * int(w);
    const int byb = std::clamp(by0 + 1, 0, int(frame.height) - 1) * int(w);
    for (uint32_t x0 = 0; x0 < W; x0 += L::kCount) {
      const uint32_t active = std::min<uint32_t>(L::kCount, W - x0);   // past the row's end: its last pixel again
      const I ox = L::min(L::splat(int(x0)) + L::kIota, lastColumn);
      const F cx = L::toFloat(ox) + 0.5f;
      const F qx = cx * sx;   // the output pixels' centres in traced pixels
      // The sample nearest to each pixel's centre and its 3 x 3 neighbourhood: colour mean and
      // deviation, the closest surface.
      const Fetch centre(L::splat(centreRow) + L::load(&nearestColumn_[x0]));
      const F meanY = centre(mean_.y), meanCo = centre(mean_.co), meanCg = centre(mean_.cg);
      const F sigmaY = centre(sigma_.y), sigmaCo = centre(sigma_.co), sigmaCg = centre(sigma_.cg);
      const F closestDepth = centre(closestDepth_);
      const I surface = centre(closestInstance_);
      // Where each pixel was: the closest surface's motion, or the sky's under the camera's turn.
      const F tracedX = centre(closestMotionX_), tracedY = centre(closestMotionY_);
      const I hasMotion = L::finite(tracedX) & L::finite(tracedY);
      F mx = L::select(hasMotion, tracedX / sx, L::splat(nan)), my = L::select(hasMotion, tracedY / sy, L::splat(nan));
      if (rays_ && previousRays_) {
        const I sky = ~hasMotion & ~L::finite(closestDepth);
        if (L::any(sky)) {
          // The ray through each pixel's centre (CameraRays::generate) projected through the last
          // frame's camera (CameraRays::project), in lanes.
          const CameraRays::Basis now = rays_->basis(), last = previousRays_->basis();
          const F rx = (2.0f * cx / now.width - 1.0f) * now.tanHalfX;
          const float ry = (1.0f - 2.0f * cy / now.height) * now.tanHalfY;
          std::array<F, 3> dir;
          for (int c = 0; c < 3; ++c) dir[size_t(c)] = now.forward[c] + rx * now.right[c] + ry * now.up[c];
          const F inverse = 1.0f / L::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
          std::array<F, 3> d;   // (last origin + dir) - last origin, as project() sees it
          for (int c = 0; c < 3; ++c) d[size_t(c)] = (last.origin[c] + dir[size_t(c)] * inverse) - last.origin[c];
          const auto dot = [&](const glm::vec3& axis) { return d[0] * axis.x + d[1] * axis.y + d[2] * axis.z; };
          const F z = dot(last.forward);
          const F px = (dot(last.right) / (z * last.tanHalfX) + 1.0f) * 0.5f * last.width;
          const F py = (1.0f - dot(last.up) / (z * last.tanHalfY)) * 0.5f * last.height;
          const I projected = sky & (z > 1e-6f) & L::finite(px) & L::finite(py);
          mx = L::select(projected, px - cx, mx);
          my = L::select(projected, py - cy, my);
        }
      }
      const F still = L::select(L::finite(mx), L::clamp(1.0f - L::sqrt(mx * mx + my * my), L::splat(0.0f), L::splat(1.0f)),
                                L::splat(0.0f));
      const F gamma = config_.clipMoving + (config_.clipStill - config_.clipMoving) * still;
      // This frame: the colour within the kernel's reach (the nearest sample where none is); a
      // moving pixel takes the wider kernel, which reaches a sample from every output pixel.
      const I moving = still < 0.5f;
      Sum sum{};
      if (!L::all(moving)) sum = kernel(laneColumns_, rows_[oy], rowD2_, invRadius2, x0);
      if (L::any(moving)) {
        const Sum wide = kernel(movingLaneColumns_, movingRows_[oy], movingRowD2_, invMovingRadius2, x0);
        sum.y = L::select(moving, wide.y, sum.y);
        sum.co = L::select(moving, wide.co, sum.co);
        sum.cg = L::select(moving, wide.cg, sum.cg);
        sum.weight = L::select(moving, wide.weight, sum.weight);
      }
      const F confidence = sum.weight;
      const I enough = confidence > 1e-4f;
      const F currentY = L::select(enough, sum.y / confidence, centre(samples_.y));
      const F currentCo = L::select(enough, sum.co / confidence, centre(samples_.co));
      const F currentCg = L::select(enough, sum.cg / confidence, centre(samples_.cg));
      F resultY = L::splat(0.0f), resultCo = resultY, resultCg = resultY;
      F weight = confidence;
      I historyUsed = zero;
      const F px = cx + mx, py = cy + my;
      const I inRange = (px >= 0.0f) & (py >= 0.0f) & (px <= static_cast<float>(W)) & (py <= static_cast<float>(H));
      if (haveHistory_ && L::any(inRange)) {
        const F fx = L::select(inRange, px - 0.5f, L::splat(0.0f)), fy = L::select(inRange, py - 0.5f, L::splat(0.0f));
        const I x1 = L::floorToInt(fx), y1 = L::floorToInt(fy);
        // The 4 x 4 history taps, clamped to the history: one load per tap where the pixels' taps
        // are consecutive history pixels (motion that changes slowly), one or two loads and a
        // permutation where they lie within a register's width on one or two rows (GridFetch).
        const bool inside = L::all(inRange & (x1 >= 1) & (y1 >= 1) & (x1 + 2 < int(W)) & (y1 + 2 < int(H)));
        // tap(plane, j, i): the history tap (x1 - 1 + i, y1 - 1 + j) of each pixel, from one plane.
        const auto merge = [&](const auto& tap) {
          // The four nearest: (x1, y1), (x1 + 1, y1), (x1, y1 + 1), (x1 + 1, y1 + 1).
          const auto nearest = [&](const auto& plane, int t) { return tap(plane, 1 + t / 2, 1 + t % 2); };
          // Disocclusion: kept where one of the four nearest history pixels showed the same instance.
          I seen = zero;
          for (int t = 0; t < 4; ++t) seen |= nearest(instance_, t) == surface;
          seen &= inRange;
          if (!L::any(seen)) return;
          const F tx = fx - L::toFloat(x1), ty = fy - L::toFloat(y1);
          const std::array<F, 4> wx = catmullRom(tx), wy = catmullRom(ty);
          // Catmull-Rom, then anti-ringing: within the four nearest taps' range.
          const auto fetchHistory = [&](const std::vector<float>& plane) {
            F s = L::splat(0.0f);
            for (size_t j = 0; j < 4; ++j) {
              const int k = int(j);
              const F r = tap(plane, k, 0) * wx[0] + tap(plane, k, 1) * wx[1] + tap(plane, k, 2) * wx[2] +
                          tap(plane, k, 3) * wx[3];
              s += r * wy[j];
            }
            F lo = nearest(plane, 0), hi = lo;
            for (int t = 1; t < 4; ++t) {
              const F v = nearest(plane, t);
              lo = L::min(lo, v);
              hi = L::max(hi, v);
            }
            s = s < lo ? lo : s;
            return s > hi ? hi : s;
          };
          F historyY = fetchHistory(history_.y), historyCo = fetchHistory(history_.co),
            historyCg = fetchHistory(history_.cg);
          const F cap = weightCap_ * (config_.movingMemory + (1.0f - config_.movingMemory) * still);
          const F historyWeight =
              L::min((1.0f - ty) * ((1.0f - tx) * nearest(weight_, 0) + tx * nearest(weight_, 1)) +
                         ty * ((1.0f - tx) * nearest(weight_, 2) + tx * nearest(weight_, 3)),
                     cap);
          // Variance clipping toward the neighbourhood mean, wider for a still pixel. A still pixel
          // keeps what last frame's samples showed too: a line thinner than a traced pixel, missed
          // by this frame's samples, is not clipped away. Not where this frame's mean left last
          // frame's box: the light changed (a muzzle flash on the weapon), and the old light goes.
          const GridFetch previousPixel(L::clamp(L::floorToInt(L::select(inRange, px, L::splat(0.0f))), zero, lastColumn),
                                        L::clamp(L::floorToInt(L::select(inRange, py, L::splat(0.0f))), zero, lastRow),
                                        int(W));
          const auto previous = [&](const std::vector<float>& plane) { return previousPixel(plane, 0, 0); };
          const F lastLoY = previous(boxLo_.y), lastHiY = previous(boxHi_.y), lastLoCo = previous(boxLo_.co),
                  lastHiCo = previous(boxHi_.co), lastLoCg = previous(boxLo_.cg), lastHiCg = previous(boxHi_.cg);
          const I sameLight = (meanY >= lastLoY) & (meanY <= lastHiY) & (meanCo >= lastLoCo) & (meanCo <= lastHiCo) &
                              (meanCg >= lastLoCg) & (meanCg <= lastHiCg);
          const F keepLast = L::select(sameLight, still, L::splat(0.0f));
          const F keep = 1.0f - keepLast;
          const auto box = [&](F mean, F sigma, F lastLo, F lastHi, F& lo, F& hi) {
            lo = mean - gamma * sigma;
            hi = mean + gamma * sigma;
            lo = L::min(lo, lo * keep + lastLo * keepLast);
            hi = L::max(hi, hi * keep + lastHi * keepLast);
          };
          F loY, hiY, loCo, hiCo, loCg, hiCg;
          box(meanY, sigmaY, lastLoY, lastHiY, loY, hiY);
          box(meanCo, sigmaCo, lastLoCo, lastHiCo, loCo, hiCo);
          box(meanCg, sigmaCg, lastLoCg, lastHiCg, loCg, hiCg);
          const F centreY = 0.5f * (loY + hiY), centreCo = 0.5f * (loCo + hiCo), centreCg = 0.5f * (loCg + hiCg);
          const F extentY = 0.5f * (hiY - loY) + 1e-3f, extentCo = 0.5f * (hiCo - loCo) + 1e-3f,
                  extentCg = 0.5f * (hiCg - loCg) + 1e-3f;
          const F offsetY = historyY - centreY, offsetCo = historyCo - centreCo, offsetCg = historyCg - centreCg;
          const F worst = L::max(L::max(L::abs(offsetY) / extentY, L::abs(offsetCo) / extentCo), L::abs(offsetCg) / extentCg);
          const I clip = worst > 1.0f;
          historyY = L::select(clip, centreY + offsetY / worst, historyY);
          historyCo = L::select(clip, centreCo + offsetCo / worst, historyCo);
          historyCg = L::select(clip, centreCg + offsetCg / worst, historyCg);
          const F total = historyWeight + confidence;
          const F alpha = L::select(total > 0.0f, confidence / total, L::splat(1.0f));
          resultY = historyY + alpha * (currentY - historyY);
          resultCo = historyCo + alpha * (currentCo - historyCo);
          resultCg = historyCg + alpha * (currentCg - historyCg);
          weight = L::select(seen, total, confidence);
          historyUsed = seen;
        };
        const GridFetch grid(x1 - 1, y1 - 1, int(W));   // used inside the history only
        if (inside && grid.kind() == Fetch::Kind::Consecutive) {
          const int first = grid.first();
          merge([&](const auto& plane, int j, int i) { return L::load(plane.data() + first + j * int(W) + i); });
        } else if (inside) {
          merge([&](const auto& plane, int j, int i) { return grid(plane, j, i); });
        } else {
          std::array<std::array<Fetch, 4>, 4> taps;
          for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i)
              taps[size_t(j)][size_t(i)] =
                  Fetch(L::clamp(y1 - 1 + j, zero, lastRow) * int(W) + L::clamp(x1 - 1 + i, zero, lastColumn));
          merge([&](const auto& plane, int j, int i) { return taps[size_t(j)][size_t(i)](plane); });
        }
      }
      // Without a history, the traced frame interpolated bilinearly (as the stretch shows it):
      // this frame's samples within the kernel alone are one sample or none per output pixel.
      if (!L::all(historyUsed)) {
        const F bx = qx - frame.jitter.x - 0.5f;
        const I bx0 = L::floorToInt(bx);
        const F btx = bx - L::toFloat(bx0);
        const I xa = L::clamp(bx0, zero, lastTracedColumn), xb = L::clamp(bx0 + 1, zero, lastTracedColumn);
        const Fetch topA(bya + xa), topB(bya + xb), bottomA(byb + xa), bottomB(byb + xb);
        const auto bilinear = [&](const std::vector<float>& plane) {
          const F top = topA(plane) + btx * (topB(plane) - topA(plane));
          const F bottom = bottomA(plane) + btx * (bottomB(plane) - bottomA(plane));
          return top + bty * (bottom - top);
        };
        resultY = L::select(historyUsed, resultY, bilinear(samples_.y));
        resultCo = L::select(historyUsed, resultCo, bilinear(samples_.co));
        resultCg = L::select(historyUsed, resultCg, bilinear(samples_.cg));
      }
      const size_t o = size_t{oy} * W + x0;
      put(nextHistory_.y, o, active, resultY);
      put(nextHistory_.co, o, active, resultCo);
      put(nextHistory_.cg, o, active, resultCg);
      put(nextWeight_, o, active, weight);
      put(nextInstance_, o, active, surface);
      put(nextBoxLo_.y, o, active, meanY - gamma * sigmaY);
      put(nextBoxLo_.co, o, active, meanCo - gamma * sigmaCo);
      put(nextBoxLo_.cg, o, active, meanCg - gamma * sigmaCg);
      put(nextBoxHi_.y, o, active, meanY + gamma * sigmaY);
      put(nextBoxHi_.co, o, active, meanCo + gamma * sigmaCo);
      put(nextBoxHi_.cg, o, active, meanCg + gamma * sigmaCg);
      // Back to RGB, encoded through the sqrt(linear) table.
      const auto code = [&](F linear) {
        return L::truncate(L::sqrt(L::clamp(linear, L::splat(0.0f), L::splat(1.0f))) *
                               static_cast<float>(kEncodeSteps - 1) +
                           0.5f);
      };
      const I r = code(resultY + resultCo - resultCg), g = code(resultY + resultCg), b = code(resultY - resultCo - resultCg);
      I rgba;   // bytes R, G, B, A in memory order (x86-64: little-endian)
      for (int l = 0; l < L::kCount; ++l)
        rgba[l] = static_cast<int32_t>(uint32_t{encode_[uint32_t(r[l])]} | uint32_t{encode_[uint32_t(g[l])]} << 8 |
                                       uint32_t{encode_[uint32_t(b[l])]} << 16 | 0xff000000u);
      if (active == L::kCount) std::memcpy(&output_[o * 4], &rgba, sizeof rgba);
      else std::memcpy(&output_[o * 4], &rgba, size_t{active} * 4);
    }
  }
}

}  // namespace pa::taau
