#include "tests/fidelity/flip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace pa::fidelity {
namespace {

using Plane = std::vector<double>;
using Mat3 = std::array<std::array<double, 3>, 3>;

// Linear sRGB (D65) to CIE XYZ, IEC 61966-2-1.
constexpr Mat3 kRgbToXyz = {{{0.4124564, 0.3575761, 0.1804375},
                             {0.2126729, 0.7151522, 0.0721750},
                             {0.0193339, 0.1191920, 0.9503041}}};

Mat3 inverse(const Mat3& m) {
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  Mat3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      // Cofactor of m[j][i] (transposed) over the determinant.
      const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
      r[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
    }
  return r;
}

std::array<double, 3> apply(const Mat3& m, double a, double b, double c) {
  return {m[0][0] * a + m[0][1] * b + m[0][2] * c, m[1][0] * a + m[1][1] * b + m[1][2] * c,
          m[2][0] * a + m[2][1] * b + m[2][2] * c};
}

double srgbDecode(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// CIELAB's companding function f(t), delta = 6/29.
double labF(double t) {
  constexpr double delta = 6.0 / 29.0;
  return t > delta * delta * delta ? std::cbrt(t) : t / (3 * delta * delta) + 4.0 / 29.0;
}

// The paper's contrast sensitivity of one opponent channel as a spatial kernel: a sum of two
// Gaussians a_k sqrt(pi / b_k) exp(-pi^2 x^2 / b_k), x in degrees.
struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kCsfAchromatic{1.0, 0.0047, 0.0, 1e-5};
constexpr Csf kCsfRedGreen{1.0, 0.0053, 0.0, 1e-5};
constexpr Csf kCsfBlueYellow{34.1, 0.04, 13.5, 0.025};
constexpr double kCsfLargestB = 0.04;    // sets the common kernel radius (3 standard deviations)

constexpr double kColourExponent = 0.7;   // q_c: compression of the HyAB distance
constexpr double kFeatureExponent = 0.5;  // q_f: compression of the feature difference
constexpr double kErrorPointC = 0.4;      // p_c: the knee of the error mapping, as a share of c_max
constexpr double kErrorPointT = 0.95;     // p_t: the error value at the knee
constexpr double kFeatureWidthDeg = 0.082;  // w: feature width in degrees (sigma = w / 2)

// Convolves rows (horizontal) or columns (vertical) with a centred 1-D kernel, clamping to edge.
Plane convolve(const Plane& in, int width, int height, const std::vector<double>& kernel, bool horizontal) {
  const int radius = static_cast<int>(kernel.size() / 2);
  Plane out(in.size());
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double sum = 0;
      for (int k = -radius; k <= radius; ++k) {
        const int sx = horizontal ? std::clamp(x + k, 0, width - 1) : x;
        const int sy = horizontal ? y : std::clamp(y + k, 0, height - 1);
        sum += kernel[static_cast<size_t>(k + radius)] * in[static_cast<size_t>(sy) * width + sx];
      }
      out[static_cast<size_t>(y) * width + x] = sum;
    }
  return out;
}

Plane separable(const Plane& in, int width, int height, const std::vector<double>& alongX,
                const std::vector<double>& alongY) {
  return convolve(convolve(in, width, height, alongX, true), width, height, alongY, false);
}

// Filters a plane with a channel's CSF kernel (2-D, normalised to sum 1): each Gaussian term is
// separable, so the 2-D kernel is the weighted sum of two separable filters.
Plane csfFilter(const Plane& in, int width, int height, const Csf& csf, double ppd) {
  const int radius = static_cast<int>(std::ceil(3 * std::sqrt(kCsfLargestB / (2 * std::numbers::pi * std::numbers::pi)) * ppd));
  const double pi2 = std::numbers::pi * std::numbers::pi;
  struct Term {
    double weight;
    std::vector<double> taps;
    double tapSum;
  };
  std::vector<Term> terms;
  double total = 0;
  for (const auto& [a, b] : {std::pair{csf.a1, csf.b1}, std::pair{csf.a2, csf.b2}}) {
    if (a == 0) continue;
    Term term{a * std::sqrt(std::numbers::pi / b), std::vector<double>(2 * radius + 1), 0};
    for (int i = -radius; i <= radius; ++i) {
      const double xDeg = i / ppd;
      term.taps[static_cast<size_t>(i + radius)] = std::exp(-pi2 * xDeg * xDeg / b);
      term.tapSum += term.taps[static_cast<size_t>(i + radius)];
    }
    total += term.weight * term.tapSum * term.tapSum;  // the 2-D term's sum
    terms.push_back(std::move(term));
  }
  Plane out(in.size(), 0.0);
  for (const Term& term : terms) {
    const Plane filtered = separable(in, width, height, term.taps, term.taps);
    for (size_t i = 0; i < out.size(); ++i) out[i] += term.weight / total * filtered[i];
  }
  return out;
}

// Hunt-adjusted CIELAB of each pixel after the CSF: L*, 0.01 L* a*, 0.01 L* b*.
struct LabPlanes {
  Plane l, a, b;
};

struct OpponentImage {
  Plane y, cx, cz;  // YyCxCz (linearised CIELAB)
};

const Mat3& xyzToRgb() {
  static const Mat3 m = inverse(kRgbToXyz);
  return m;
}

std::array<double, 3> whitePoint() { return apply(kRgbToXyz, 1, 1, 1); }

OpponentImage toOpponent(const RgbImage& image) {
  std::array<double, 256> decoded{};
  for (int i = 0; i < 256; ++i) decoded[static_cast<size_t>(i)] = srgbDecode(i / 255.0);
  const auto white = whitePoint();
  const size_t count = static_cast<size_t>(image.width) * image.height;
  OpponentImage out{Plane(count), Plane(count), Plane(count)};
  for (size_t i = 0; i < count; ++i) {
    const std::uint8_t* p = &image.pixels[3 * i];
    const auto xyz = apply(kRgbToXyz, decoded[p[0]], decoded[p[1]], decoded[p[2]]);
    const double xr = xyz[0] / white[0], yr = xyz[1] / white[1], zr = xyz[2] / white[2];
    out.y[i] = 116 * yr - 16;
    out.cx[i] = 500 * (xr - yr);
    out.cz[i] = 200 * (yr - zr);
  }
  return out;
}

std::array<double, 3> huntLab(double r, double g, double b) {
  const auto white = whitePoint();
  const auto xyz = apply(kRgbToXyz, r, g, b);
  const double fx = labF(xyz[0] / white[0]), fy = labF(xyz[1] / white[1]), fz = labF(xyz[2] / white[2]);
  const double l = 116 * fy - 16;
  return {l, 0.01 * l * 500 * (fx - fy), 0.01 * l * 200 * (fy - fz)};
}

LabPlanes filteredHuntLab(const OpponentImage& in, int width, int height, double ppd) {
  const Plane y = csfFilter(in.y, width, height, kCsfAchromatic, ppd);
  const Plane cx = csfFilter(in.cx, width, height, kCsfRedGreen, ppd);
  const Plane cz = csfFilter(in.cz, width, height, kCsfBlueYellow, ppd);
  const auto white = whitePoint();
  LabPlanes out{Plane(y.size()), Plane(y.size()), Plane(y.size())};
  for (size_t i = 0; i < y.size(); ++i) {
    const double yr = (y[i] + 16) / 116;
    const double xr = cx[i] / 500 + yr, zr = yr - cz[i] / 200;
    auto rgb = apply(xyzToRgb(), xr * white[0], yr * white[1], zr * white[2]);
    for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);  // back into the display's gamut
    const auto lab = huntLab(rgb[0], rgb[1], rgb[2]);
    out.l[i] = lab[0];
    out.a[i] = lab[1];
    out.b[i] = lab[2];
  }
  return out;
}

double hyab(const std::array<double, 3>& p, const std::array<double, 3>& q) {
  return std::abs(p[0] - q[0]) + std::hypot(p[1] - q[1], p[2] - q[2]);
}

// The largest colour distance: between the display's green and blue primaries, compressed.
double maxColourError() {
  static const double value = std::pow(hyab(huntLab(0, 1, 0), huntLab(0, 0, 1)), kColourExponent);
  return value;
}

// Maps the compressed HyAB distance to [0, 1]: linear up to p_c * c_max (reaching p_t there),
// then linear from p_t to 1 at c_max.
double mapColourError(double compressed) {
  const double cmax = maxColourError(), knee = kErrorPointC * cmax;
  if (compressed < knee) return kErrorPointT / knee * compressed;
  return kErrorPointT + (compressed - knee) / (cmax - knee) * (1 - kErrorPointT);
}

// 1-D Gaussian (sum 1) and its first and second derivatives, each derivative scaled so its
// positive taps sum to 1 and its negative taps to -1; sigma = w / 2 degrees.
struct FeatureKernels {
  std::vector<double> gauss, first, second;
};

FeatureKernels featureKernels(double ppd) {
  const double sigma = 0.5 * kFeatureWidthDeg * ppd;
  const int radius = static_cast<int>(std::ceil(3 * sigma));
  FeatureKernels k{std::vector<double>(2 * radius + 1), std::vector<double>(2 * radius + 1),
                   std::vector<double>(2 * radius + 1)};
  for (int i = -radius; i <= radius; ++i) {
    const double x = i, g = std::exp(-x * x / (2 * sigma * sigma));
    const size_t at = static_cast<size_t>(i + radius);
    k.gauss[at] = g;
    k.first[at] = -x * g;
    k.second[at] = (x * x / (sigma * sigma) - 1) * g;
  }
  double gaussSum = 0;
  for (double v : k.gauss) gaussSum += v;
  for (double& v : k.gauss) v /= gaussSum;
  for (auto* taps : {&k.first, &k.second}) {
    double positive = 0, negative = 0;
    for (double v : *taps) (v > 0 ? positive : negative) += v;
    for (double& v : *taps) v = v > 0 ? v / positive : v / -negative;
  }
  return k;
}

// Edge and point strength (gradient magnitude of the first and second derivative filters) of
// the normalised achromatic channel Y / Yn.
struct Features {
  Plane edge, point;
};

Features features(const Plane& achromatic, int width, int height, const FeatureKernels& k) {
  const Plane ex = separable(achromatic, width, height, k.first, k.gauss);
  const Plane ey = separable(achromatic, width, height, k.gauss, k.first);
  const Plane px = separable(achromatic, width, height, k.second, k.gauss);
  const Plane py = separable(achromatic, width, height, k.gauss, k.second);
  Features out{Plane(achromatic.size()), Plane(achromatic.size())};
  for (size_t i = 0; i < achromatic.size(); ++i) {
    out.edge[i] = std::hypot(ex[i], ey[i]);
    out.point[i] = std::hypot(px[i], py[i]);
  }
  return out;
}

}  // namespace

double pixelsPerDegree(double distanceM, double monitorWidthM, double monitorWidthPx) {
  return distanceM * (monitorWidthPx / monitorWidthM) * std::numbers::pi / 180.0;
}

double flipDefaultPixelsPerDegree() { return pixelsPerDegree(0.7, 0.7, 3840); }

FlipMap flip(const RgbImage& reference, const RgbImage& test, double ppd) {
  if (reference.width != test.width || reference.height != test.height)
    throw std::invalid_argument("flip: sizes differ");
  if (reference.width <= 0 || reference.height <= 0) throw std::invalid_argument("flip: empty image");
  if (!(ppd > 0)) throw std::invalid_argument("flip: pixels per degree must be positive");
  const int width = reference.width, height = reference.height;
  const OpponentImage refOpp = toOpponent(reference), testOpp = toOpponent(test);

  // Colour: CSF-filtered, Hunt-adjusted CIELAB, HyAB distance, compressed and mapped to [0, 1].
  const LabPlanes refLab = filteredHuntLab(refOpp, width, height, ppd);
  const LabPlanes testLab = filteredHuntLab(testOpp, width, height, ppd);

  // Features: edges and points of the unfiltered achromatic channel, Y / Yn = (Yy + 16) / 116.
  const FeatureKernels kernels = featureKernels(ppd);
  Plane refY(refOpp.y.size()), testY(testOpp.y.size());
  for (size_t i = 0; i < refY.size(); ++i) {
    refY[i] = (refOpp.y[i] + 16) / 116;
    testY[i] = (testOpp.y[i] + 16) / 116;
  }
  const Features refF = features(refY, width, height, kernels), testF = features(testY, width, height, kernels);

  FlipMap map{width, height, std::vector<float>(refY.size()), 0};
  double sum = 0;
  for (size_t i = 0; i < refY.size(); ++i) {
    const double distance = hyab({refLab.l[i], refLab.a[i], refLab.b[i]}, {testLab.l[i], testLab.a[i], testLab.b[i]});
    const double colour = mapColourError(std::pow(distance, kColourExponent));
    const double featureDiff = std::max(std::abs(refF.edge[i] - testF.edge[i]), std::abs(refF.point[i] - testF.point[i]));
    const double feature = std::pow(std::min(1.0, featureDiff / std::numbers::sqrt2), kFeatureExponent);
    const double error = colour > 0 ? std::pow(colour, 1 - feature) : 0.0;  // 0^0 where nothing differs
    map.error[i] = static_cast<float>(error);
    sum += error;
  }
  map.mean = sum / static_cast<double>(refY.size());
  return map;
}

RgbImage flipErrorImage(const FlipMap& map) {
  RgbImage out{map.width, map.height, std::vector<std::uint8_t>(map.error.size() * 3)};
  for (size_t i = 0; i < map.error.size(); ++i) {
    const auto v = static_cast<std::uint8_t>(std::lround(std::clamp(map.error[i], 0.0f, 1.0f) * 255));
    out.pixels[3 * i] = out.pixels[3 * i + 1] = out.pixels[3 * i + 2] = v;
  }
  return out;
}

}  // namespace pa::fidelity
