#include "renderer/scene/denoise/fireflies.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "renderer/scene/sampling/warp.h"

namespace pa::denoise {
namespace {

using sampling::luminance;

/// Whether pixels a and b see the same surface (symmetric in a and b).
bool sameSurface(const FireflyInputs& in, const FireflyConfig& config, size_t a, size_t b) {
  const float da = in.depth[a], db = in.depth[b];
  if (!std::isfinite(da) || !std::isfinite(db)) return false;
  if (std::fabs(da - db) > config.depthTolerance * std::max(da, db)) return false;
  return glm::dot(in.normal[a], in.normal[b]) >= config.normalCosine;
}

}  // namespace

uint32_t spreadFireflies(const FireflyInputs& in, std::span<glm::vec3> radiance, const FireflyConfig& config) {
  FireflyScratch scratch;
  return spreadFireflies(in, radiance, scratch, config);
}

uint32_t spreadFireflies(const FireflyInputs& in, std::span<glm::vec3> radiance, FireflyScratch& scratch,
                         const FireflyConfig& config) {
  const size_t n = size_t{in.width} * in.height;
  if (radiance.size() != n || in.emission.size() != n || in.normal.size() != n || in.depth.size() != n)
    throw std::invalid_argument("spreadFireflies: buffers of " + std::to_string(radiance.size()) + ", " +
                                std::to_string(in.emission.size()) + ", " + std::to_string(in.normal.size()) + ", " +
                                std::to_string(in.depth.size()) + " pixels for " + std::to_string(n));
  if (n == 0) return 0;
  const int w = int(in.width), h = int(in.height), r = int(std::min<uint32_t>(config.radius, 16));
  std::vector<float>& lum = scratch.luminance;
  lum.resize(n);
  for (size_t i = 0; i < n; ++i)
    lum[i] = std::isfinite(in.depth[i]) ? std::max(0.0f, luminance(radiance[i] - in.emission[i])) : 0.0f;
  const auto forRows = [&](auto&& body) {
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y) body(y);
    });
  };
  // Summed-area tables of the luminance and of the geometry pixels: any window's sum in O(1).
  const size_t stride = size_t(w) + 1;
  std::vector<double>& lumSum = scratch.luminanceSums;
  std::vector<uint32_t>& geometrySum = scratch.geometrySums;
  lumSum.assign(stride * (size_t(h) + 1), 0.0);
  geometrySum.assign(stride * (size_t(h) + 1), 0);
  for (int y = 0; y < h; ++y) {
    double rowLum = 0.0;
    uint32_t rowGeometry = 0;
    for (int x = 0; x < w; ++x) {
      const size_t p = size_t(y) * size_t(w) + size_t(x);
      rowLum += lum[p];
      rowGeometry += std::isfinite(in.depth[p]) ? 1u : 0u;
      lumSum[(size_t(y) + 1) * stride + size_t(x) + 1] = lumSum[size_t(y) * stride + size_t(x) + 1] + rowLum;
      geometrySum[(size_t(y) + 1) * stride + size_t(x) + 1] = geometrySum[size_t(y) * stride + size_t(x) + 1] + rowGeometry;
    }
  }
  const auto windowSum = [&](const auto& table, int x, int y) {
    const size_t x0 = size_t(std::max(0, x - r)), x1 = size_t(std::min(w, x + r + 1));
    const size_t y0 = size_t(std::max(0, y - r)), y1 = size_t(std::min(h, y + r + 1));
    return table[y1 * stride + x1] - table[y0 * stride + x1] - table[y1 * stride + x0] + table[y0 * stride + x0];
  };
  // Pass 1: each firefly's excess (lit radiance above the cut) and the share each receiver gets.
  std::vector<glm::vec3>& excess = scratch.excess;
  std::vector<float>& share = scratch.share;
  std::vector<uint8_t>& rowCuts = scratch.rowCuts;
  excess.assign(n, glm::vec3(0.0f));
  share.assign(n, 0.0f);
  rowCuts.assign(size_t(h), 0);   // rows with a firefly (each written by its own row)
  std::atomic<uint32_t> cut{0};
  forRows([&](int y) {
    uint32_t rowCut = 0;
    for (int x = 0; x < w; ++x) {
      const size_t p = size_t(y) * size_t(w) + size_t(x);
      if (!(lum[p] > config.floor)) continue;
      const double sum = windowSum(lumSum, x, y) - double(lum[p]);   // the neighbours, itself left out
      const uint32_t count = windowSum(geometrySum, x, y) - 1u;
      const float level = std::max(config.floor, config.ratio * (count > 0 ? float(sum / count) : 0.0f));
      if (!(lum[p] > level)) continue;
      int receivers = 0;
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          if (sameSurface(in, config, p, size_t(qy) * size_t(w) + size_t(qx))) ++receivers;
        }
      if (receivers <= 1) continue;   // nobody to share with: left as it is
      excess[p] = (radiance[p] - in.emission[p]) * (1.0f - level / lum[p]);
      share[p] = 1.0f / float(receivers);
      ++rowCut;
    }
    rowCuts[size_t(y)] = rowCut > 0 ? 1 : 0;
    cut += rowCut;
  });
  if (cut == 0) return 0;
  // Pass 2, per row (rows are independent): cut this row's fireflies and add the shares it
  // receives from the fireflies of the rows around it, always in the same order.
  std::vector<glm::vec3>& out = scratch.out;
  out.assign(radiance.begin(), radiance.end());
  forRows([&](int y) {
    const size_t row = size_t(y) * size_t(w);
    for (int x = 0; x < w; ++x) out[row + size_t(x)] -= excess[row + size_t(x)];
    for (int py = std::max(0, y - r); py <= std::min(h - 1, y + r); ++py) {
      if (rowCuts[size_t(py)] == 0) continue;
      for (int px = 0; px < w; ++px) {
        const size_t p = size_t(py) * size_t(w) + size_t(px);
        if (!(share[p] > 0.0f)) continue;
        const glm::vec3 part = excess[p] * share[p];
        for (int qx = std::max(0, px - r); qx <= std::min(w - 1, px + r); ++qx)
          if (sameSurface(in, config, p, row + size_t(qx))) out[row + size_t(qx)] += part;
      }
    }
  });
  std::copy(out.begin(), out.end(), radiance.begin());
  return cut;
}

}  // namespace pa::denoise
