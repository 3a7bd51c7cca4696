#include "tests/regress/compare/flip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace pa::regress {
namespace {

using Vec3 = std::array<double, 3>;

// D65 reference white in XYZ (Y = 1).
constexpr Vec3 kWhite = {0.950428545, 1.0, 1.088900371};

// Linear sRGB (Rec. 709 primaries, D65) <-> CIE XYZ.
constexpr double kRgbToXyz[3][3] = {{0.4123908, 0.3575843, 0.1804808},
                                    {0.2126390, 0.7151687, 0.0721923},
                                    {0.0193308, 0.1191948, 0.9505322}};
constexpr double kXyzToRgb[3][3] = {{3.2409699, -1.5373832, -0.4986108},
                                    {-0.9692436, 1.8759675, 0.0415551},
                                    {0.0556301, -0.2039770, 1.0569715}};

Vec3 multiply(const double m[3][3], const Vec3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

double srgbToLinear(double c) { return c > 0.04045 ? std::pow((c + 0.055) / 1.055, 2.4) : c / 12.92; }

// YCxCz: the linear opponent space of the paper (CIELAB's formulas without the cube root).
Vec3 xyzToYcxcz(const Vec3& xyz) {
  const double x = xyz[0] / kWhite[0], y = xyz[1] / kWhite[1], z = xyz[2] / kWhite[2];
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Vec3 ycxczToXyz(const Vec3& c) {
  const double y = (c[0] + 16.0) / 116.0;
  return {(y + c[1] / 500.0) * kWhite[0], y * kWhite[1], (y - c[2] / 200.0) * kWhite[2]};
}

// CIELAB of linear RGB, then the Hunt adjustment (chroma scaled by 0.01 L).
Vec3 huntLab(const Vec3& linearRgb) {
  const Vec3 xyz = multiply(kRgbToXyz, linearRgb);
  constexpr double delta = 6.0 / 29.0;
  auto f = [&](double t) { return t > delta * delta * delta ? std::cbrt(t) : t / (3 * delta * delta) + 4.0 / 29.0; };
  const double fx = f(xyz[0] / kWhite[0]), fy = f(xyz[1] / kWhite[1]), fz = f(xyz[2] / kWhite[2]);
  const double l = 116.0 * fy - 16.0;
  return {l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)};
}

// HyAB: city-block lightness plus Euclidean chroma distance.
double hyab(const Vec3& a, const Vec3& b) {
  return std::abs(a[0] - b[0]) + std::hypot(a[1] - b[1], a[2] - b[2]);
}

// A separable kernel: a sum of terms, each weights x[dx] * y[dy] for dx, dy in [-radius, radius].
struct SeparableTerm {
  std::vector<double> x, y;
};
struct Kernel {
  int radius = 0;
  std::vector<SeparableTerm> terms;
};

// Correlates one plane with a kernel, replicating the border pixels (rows, then columns).
std::vector<double> filter(const std::vector<double>& plane, int width, int height, const Kernel& k) {
  std::vector<double> out(plane.size(), 0.0), rows(plane.size());
  for (const SeparableTerm& term : k.terms) {
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        double sum = 0;
        for (int d = -k.radius; d <= k.radius; ++d)
          sum += term.x[d + k.radius] * plane[static_cast<size_t>(y) * width + std::clamp(x + d, 0, width - 1)];
        rows[static_cast<size_t>(y) * width + x] = sum;
      }
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        double sum = 0;
        for (int d = -k.radius; d <= k.radius; ++d)
          sum += term.y[d + k.radius] * rows[static_cast<size_t>(std::clamp(y + d, 0, height - 1)) * width + x];
        out[static_cast<size_t>(y) * width + x] += sum;
      }
  }
  return out;
}

// Contrast sensitivity of one opponent channel as a sum of two Gaussians in visual degrees
// (the paper's Table 1), sampled at the pixel pitch and normalised to sum 1 over the square
// (2 radius + 1)^2. The radius covers three standard deviations of the widest Gaussian of all
// three channels. Each Gaussian exp(-pi^2 (dx^2 + dy^2) / b) is the product of two 1D ones.
Kernel csfKernel(double a1, double b1, double a2, double b2, double ppd) {
  constexpr double kWidestB = 0.04;
  const double pi = std::numbers::pi;
  Kernel k;
  k.radius = static_cast<int>(std::ceil(3.0 * std::sqrt(kWidestB / (2.0 * pi * pi)) * ppd));
  double total = 0;
  for (auto [a, b] : {std::pair{a1, b1}, std::pair{a2, b2}}) {
    if (a == 0) continue;
    SeparableTerm t;
    double sum1d = 0;
    for (int d = -k.radius; d <= k.radius; ++d) {
      t.x.push_back(std::exp(-pi * pi * (d * d) / (ppd * ppd) / b));
      sum1d += t.x.back();
    }
    for (double& w : t.x) w *= a * std::sqrt(pi / b);
    t.y.assign(t.x.size(), 0.0);
    for (size_t i = 0; i < t.x.size(); ++i) t.y[i] = t.x[i] / (a * std::sqrt(pi / b));
    total += a * std::sqrt(pi / b) * sum1d * sum1d;
    k.terms.push_back(std::move(t));
  }
  for (SeparableTerm& t : k.terms)
    for (double& w : t.x) w /= total;
  return k;
}

// Edge (first derivative of a Gaussian along x) or point (second derivative) detector with
// standard deviation half the human edge detector's peak-to-trough width 0.082 degrees; over the
// square, positive weights normalised to sum 1 and negative ones to -1. The 2D weight is
// f(dx) g(dy) with g > 0, so those sums factor into the x part's positive (negative) sum times
// the sum of g. `alongY` gives the transposed kernel.
Kernel featureKernel(bool secondDerivative, double ppd, bool alongY) {
  const double sd = 0.5 * 0.082 * ppd;
  Kernel k;
  k.radius = static_cast<int>(std::ceil(3.0 * sd));
  SeparableTerm t;
  double positive = 0, negative = 0, gaussSum = 0;
  for (int d = -k.radius; d <= k.radius; ++d) {
    const double g = std::exp(-(d * d) / (2 * sd * sd));
    const double f = secondDerivative ? (d * d / (sd * sd) - 1.0) * g : -d * g;
    t.x.push_back(f);
    t.y.push_back(g);
    (f > 0 ? positive : negative) += f;
    gaussSum += g;
  }
  for (double& f : t.x) f = f > 0 ? f / (positive * gaussSum) : (f < 0 ? f / (-negative * gaussSum) : 0.0);
  if (alongY) std::swap(t.x, t.y);
  k.terms.push_back(std::move(t));
  return k;
}

struct Prepared {
  std::vector<Vec3> hunt;        // Hunt-adjusted CIELAB of the CSF-filtered image
  std::vector<double> edge;      // edge detector magnitude on the achromatic channel
  std::vector<double> point;     // point detector magnitude on the achromatic channel
};

Prepared prepare(const std::vector<std::uint8_t>& srgb, int width, int height, double ppd) {
  const size_t n = static_cast<size_t>(width) * height;
  std::array<std::vector<double>, 3> opponent;
  for (auto& plane : opponent) plane.resize(n);
  std::vector<double> achromatic(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec3 linear = {srgbToLinear(srgb[3 * i] / 255.0), srgbToLinear(srgb[3 * i + 1] / 255.0),
                         srgbToLinear(srgb[3 * i + 2] / 255.0)};
    const Vec3 c = xyzToYcxcz(multiply(kRgbToXyz, linear));
    for (int ch = 0; ch < 3; ++ch) opponent[ch][i] = c[ch];
    achromatic[i] = (c[0] + 16.0) / 116.0;
  }
  const std::array<Kernel, 3> csf = {csfKernel(1.0, 0.0047, 0.0, 1e-5, ppd), csfKernel(1.0, 0.0053, 0.0, 1e-5, ppd),
                                     csfKernel(34.1, 0.04, 13.5, 0.025, ppd)};
  for (int ch = 0; ch < 3; ++ch) opponent[ch] = filter(opponent[ch], width, height, csf[ch]);

  Prepared p;
  p.hunt.resize(n);
  for (size_t i = 0; i < n; ++i) {
    Vec3 rgb = multiply(kXyzToRgb, ycxczToXyz({opponent[0][i], opponent[1][i], opponent[2][i]}));
    for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);
    p.hunt[i] = huntLab(rgb);
  }
  const auto ex = filter(achromatic, width, height, featureKernel(false, ppd, false));
  const auto ey = filter(achromatic, width, height, featureKernel(false, ppd, true));
  const auto px = filter(achromatic, width, height, featureKernel(true, ppd, false));
  const auto py = filter(achromatic, width, height, featureKernel(true, ppd, true));
  p.edge.resize(n);
  p.point.resize(n);
  for (size_t i = 0; i < n; ++i) {
    p.edge[i] = std::hypot(ex[i], ey[i]);
    p.point[i] = std::hypot(px[i], py[i]);
  }
  return p;
}

}  // namespace

double defaultPixelsPerDegree() { return 0.7 * 3840.0 / 0.7 * std::numbers::pi / 180.0; }

std::vector<float> flipErrorMap(const std::vector<std::uint8_t>& reference, const std::vector<std::uint8_t>& test,
                                int width, int height, double pixelsPerDegree) {
  const size_t n = static_cast<size_t>(width) * height;
  if (width <= 0 || height <= 0 || reference.size() != 3 * n || test.size() != 3 * n)
    throw std::invalid_argument("flipErrorMap: images must both be width x height x 3 bytes");
  constexpr double qc = 0.7, qf = 0.5, pc = 0.4, pt = 0.95;
  const Prepared r = prepare(reference, width, height, pixelsPerDegree);
  const Prepared t = prepare(test, width, height, pixelsPerDegree);
  // The largest colour difference: Hunt-adjusted pure green against pure blue.
  const double cmax = std::pow(hyab(huntLab({0, 1, 0}), huntLab({0, 0, 1})), qc);
  std::vector<float> out(n);
  for (size_t i = 0; i < n; ++i) {
    const double e = std::pow(hyab(r.hunt[i], t.hunt[i]), qc);
    // Errors below pc * cmax fill [0, pt], the rest (pt, 1].
    const double colour = e < pc * cmax ? pt * e / (pc * cmax) : pt + (e - pc * cmax) / (cmax - pc * cmax) * (1.0 - pt);
    const double feature = std::pow(std::max(std::abs(r.edge[i] - t.edge[i]), std::abs(r.point[i] - t.point[i])) /
                                        std::numbers::sqrt2, qf);
    out[i] = static_cast<float>(std::clamp(std::pow(colour, 1.0 - feature), 0.0, 1.0));
  }
  return out;
}

}  // namespace pa::regress
