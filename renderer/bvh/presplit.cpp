// Triangle pre-splitting (see presplit.h).
//
// 1. Priority per triangle: p = (w * A_box)^(1/4): A_box is the half area of its box, w = 2^-d
//    with d the depth of the coarsest grid plane crossing its box (d = 1 halves the mesh box): large
//    boxes across coarse planes are what keeps the top of the tree from separating its
//    children. (The box's excess over the triangle's projected areas, as in Karras & Aila, was
//    measured too: it never splits long axis-aligned slivers, whose boxes fit them; neither is
//    better at every budget, docs/performance.md "Pre-splitting".) The fourth root spreads the budget wider.
//    "Crossing" means inside the middle three quarters of the box on that axis: planes near a
//    box's end would cut off slivers that cost a reference and save next to nothing.
// 2. Splits per triangle: min(cap, floor(D * p)), D the largest scale whose total fits the budget
//    (bisection on exact integer totals, so the plan does not depend on the thread count).
// 3. A triangle with s splits: its box is cut at the coarsest grid plane crossing it (of
//    equally coarse ones on several axes, the one leaving the smallest boxes; a cut that leaves
//    the same total area, as along a sliver, still lets the tree separate the halves), each
//    side gets the conservative box of the triangle's part in it, and the other s - 1 splits go
//    to the sides in proportion to their half areas; recursively.
#include "renderer/bvh/presplit.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <glm/vec3.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace pa::bvh_detail {
namespace {

constexpr int kGridBits = 20;                        // finest grid: 2^20 cells per axis
constexpr uint32_t kGridCells = 1u << kGridBits;
constexpr uint32_t kMaxSplitsPerTriangle = 64;
constexpr double kUnitRoundoff = 0x1p-53;
constexpr uint32_t kGrain = 1 << 12;

using DVec = glm::dvec3;

/// The next float towards -inf (f finite; the bit pattern steps by one).
float nextDown(float f) {
  if (f == 0.0f) return -std::numeric_limits<float>::denorm_min();
  const auto bits = std::bit_cast<uint32_t>(f);
  return std::bit_cast<float>(f > 0.0f ? bits - 1 : bits + 1);
}
/// The largest float <= x and the smallest float >= x (x within the float range).
float roundDown(double x) {
  const float f = static_cast<float>(x);
  return double(f) > x ? nextDown(f) : f;
}
float roundUp(double x) { return -roundDown(-x); }

/// Box in double, for the candidate extreme points of a clipped triangle.
struct DBox {
  DVec min{std::numeric_limits<double>::infinity()};
  DVec max{-std::numeric_limits<double>::infinity()};
  void extend(const DVec& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
};

bool insideClosed(const Bounds& cell, const glm::vec3& p) {
  for (int a = 0; a < 3; ++a)
    if (!(p[a] >= cell.min[a] && p[a] <= cell.max[a])) return false;
  return true;
}

/// Intersection of two boxes (empty when they do not overlap).
Bounds intersect(const Bounds& a, const Bounds& b) {
  Bounds r;
  r.min = glm::max(a.min, b.min);
  r.max = glm::min(a.max, b.max);
  return r;
}

Bounds triangleBox(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  Bounds box;
  box.extend(a);
  box.extend(b);
  box.extend(c);
  return box;
}

/// Half surface area in double (float overflows from extents of ~1e19); 0 for an empty box.
double halfArea(const Bounds& b) {
  if (b.empty()) return 0.0;
  const DVec d = DVec(b.max) - DVec(b.min);
  return d.x * d.y + d.y * d.z + d.z * d.x;
}

/// Rounding error of the double sum s = fl(a + b) (TwoSum: exact).
double sumError(double a, double b, double s) {
  const double bv = s - a;
  return (a - (s - bv)) + (b - bv);
}

/// 2D cross product of (b - a) and (p - a) in the plane of axes (x, y), in double.
double edgeFunction(const DVec& a, const DVec& b, double px, double py, int x, int y) {
  return (b[x] - a[x]) * (py - a[y]) - (b[y] - a[y]) * (px - a[x]);
}

/// Whether edgeFunction(a, b, px, py, x, y) is exact (none of its operations rounded).
bool edgeFunctionIsExact(const DVec& a, const DVec& b, double px, double py, int x, int y) {
  const double d1 = b[x] - a[x], d2 = py - a[y], d3 = b[y] - a[y], d4 = px - a[x];
  const double p1 = d1 * d2, p2 = d3 * d4;
  return sumError(b[x], -a[x], d1) == 0.0 && sumError(py, -a[y], d2) == 0.0 && sumError(b[y], -a[y], d3) == 0.0 &&
         sumError(px, -a[x], d4) == 0.0 && std::fma(d1, d2, -p1) == 0.0 && std::fma(d3, d4, -p2) == 0.0 &&
         sumError(p1, -p2, p1 - p2) == 0.0;
}

/// A grid plane: axis (-1 = none), level (larger = coarser: the bit that changes) and position.
struct GridPlane {
  int axis = -1;
  int level = -1;
  float position = 0.0f;
};

/// Power-of-two grid over the mesh box. The plane at integer coordinate k along an axis has
/// level = countr_zero(k): the coarsest plane crossing a box is the one where the integer
/// coordinates of its two ends differ in the highest bit.
class Grid {
 public:
  explicit Grid(const Bounds& box) : origin_(box.min) {
    for (int a = 0; a < 3; ++a) {
      const float extent = box.max[a] - box.min[a];
      cell_[a] = extent / float(kGridCells);
      inverseCell_[a] = extent > 0.0f ? float(kGridCells) / extent : 0.0f;
    }
  }

  /// The coarsest plane on `axis` strictly inside the middle of box (its outer eighths are
  /// left out: a plane there would cut off a sliver); axis -1 when there is none.
  GridPlane coarsestPlane(const Bounds& box, int axis) const {
    const float margin = 0.125f * (box.max[axis] - box.min[axis]);
    const float min = box.min[axis] + margin, max = box.max[axis] - margin;
    uint32_t lo = cellOf(min, axis), hi = cellOf(max, axis);
    while (lo < hi) {
      const int level = std::bit_width(lo ^ hi) - 1;
      const uint32_t index = hi >> level << level;   // in (lo, hi]
      const float position = origin_[axis] + float(index) * cell_[axis];
      if (position >= max) {
        hi = index - 1;   // a range ending on a plane: look below it
      } else if (position <= min) {
        lo = index;       // (rounding) starting on it: look above it
      } else {
        return {axis, level, position};
      }
    }
    return {};
  }

  /// The coarsest plane in the middle of box on any axis (ties: the longer axis, then the lower).
  GridPlane coarsestPlane(const Bounds& box) const {
    GridPlane best;
    float bestExtent = -1.0f;
    for (int a = 0; a < 3; ++a) {
      const GridPlane plane = coarsestPlane(box, a);
      const float extent = box.max[a] - box.min[a];
      if (plane.axis >= 0 && (plane.level > best.level || (plane.level == best.level && extent > bestExtent))) {
        best = plane;
        bestExtent = extent;
      }
    }
    return best;
  }

 private:
  uint32_t cellOf(float x, int axis) const {
    const float q = (x - origin_[axis]) * inverseCell_[axis];
    if (!(q > 0.0f)) return 0;
    return q >= float(kGridCells - 1) ? kGridCells - 1 : static_cast<uint32_t>(q);
  }

  glm::vec3 origin_, cell_{0.0f}, inverseCell_{0.0f};
};

/// Splits one triangle's box `s` times and writes its references.
class TriangleSplitter {
 public:
  TriangleSplitter(const Grid& grid, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, uint32_t tri,
                   SplitRef* out)
      : grid_(grid), a_(a), b_(b), c_(c), tri_(tri), out_(out) {}

  /// Writes the references of box (split `splits` times where possible); returns their count.
  uint32_t run(const Bounds& box, uint32_t splits) {
    split(box, splits);
    return written_;
  }

 private:
  /// Cuts at the coarsest grid plane crossing box (the one the top of the tree is most likely
  /// to split at); where several axes offer one of the same level, at the one whose two parts
  /// have the smallest boxes (sum of half areas). No split where the boxes would grow.
  void split(const Bounds& box, uint32_t splits) {
    GridPlane planes[3];
    int coarsest = -1;
    for (int axis = 0; axis < 3 && splits > 0; ++axis) {
      planes[axis] = grid_.coarsestPlane(box, axis);
      coarsest = std::max(coarsest, planes[axis].level);
    }
    Bounds bestLeft, bestRight;
    double bestArea = halfArea(box);
    int bestLevel = -1;
    for (int axis = 0; axis < 3 && coarsest >= 0; ++axis) {
      const GridPlane& plane = planes[axis];
      if (plane.axis < 0 || plane.level != coarsest) continue;
      Bounds leftCell = box, rightCell = box;
      leftCell.max[axis] = plane.position;
      rightCell.min[axis] = plane.position;
      const Bounds left = clippedTriangleBounds(a_, b_, c_, leftCell);
      const Bounds right = clippedTriangleBounds(a_, b_, c_, rightCell);
      if (left.empty() || right.empty()) continue;
      const double area = halfArea(left) + halfArea(right);
      if (area < bestArea || (bestLevel < 0 && area == bestArea)) {
        bestArea = area;
        bestLevel = plane.level;
        bestLeft = left;
        bestRight = right;
      }
    }
    if (bestLevel < 0) {
      out_[written_++] = {box.min, tri_, box.max, 0u};
      return;
    }
    const double wl = halfArea(bestLeft), wr = halfArea(bestRight);
    const uint32_t rest = splits - 1;
    const double share = wl / (wl + wr);   // NaN for 0 / 0: halve
    const uint32_t toLeft = share >= 0.0 && share <= 1.0 ? static_cast<uint32_t>(std::lround(rest * share)) : rest / 2;
    split(bestLeft, toLeft);
    split(bestRight, rest - toLeft);
  }

  const Grid& grid_;
  glm::vec3 a_, b_, c_;
  uint32_t tri_;
  SplitRef* out_;
  uint32_t written_ = 0;
};

/// Sum over triangles of min(cap, floor(scale * priority)).
uint64_t totalSplits(std::span<const float> priority, float scale) {
  uint64_t total = 0;
  // Blocks of int32 sums (at most 2^16 * 64 each) keep the loop vectorisable.
  for (size_t begin = 0; begin < priority.size(); begin += 1 << 16) {
    const size_t end = std::min(priority.size(), begin + (1 << 16));
    int32_t block = 0;
    for (size_t i = begin; i < end; ++i) block += static_cast<int32_t>(std::min(scale * priority[i], float(kMaxSplitsPerTriangle)));
    total += static_cast<uint64_t>(block);
  }
  return total;
}

/// The largest scale (to bisection precision) whose total does not exceed budget.
float splitScale(std::span<const float> priority, uint64_t budget) {
  double sum = 0.0;
  for (const float p : priority) sum += p;
  if (sum <= 0.0 || budget == 0) return 0.0f;
  float lo = 0.0f, hi = static_cast<float>(double(budget) / sum);
  for (int i = 0; i < 40 && totalSplits(priority, hi) <= budget; ++i) {
    lo = hi;
    hi *= 2.0f;
    if (!std::isfinite(hi)) return lo;
  }
  for (int i = 0; i < 12; ++i) {   // the total to within ~0.1 % of the budget
    const float mid = 0.5f * (lo + hi);
    (totalSplits(priority, mid) <= budget ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

Bounds clippedTriangleBounds(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const Bounds& cell) {
  const Bounds triBox = triangleBox(a, b, c);
  const Bounds limit = intersect(triBox, cell);
  if (limit.empty()) return Bounds{};
  if (insideClosed(cell, triBox.min) && insideClosed(cell, triBox.max)) return triBox;
  const std::array<DVec, 3> v{DVec(a), DVec(b), DVec(c)};
  double magnitude = 0.0;
  for (const DVec& p : v) magnitude = std::max({magnitude, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
  // Every candidate point below is within 2^-46 * magnitude of exact (see each case); pad more.
  const double pad = magnitude * 0x1p-40;
  const DVec cellMin(cell.min), cellMax(cell.max);
  auto nearCell = [&](const DVec& p, int skipAxis) {
    for (int k = 0; k < 3; ++k)
      if (k != skipAxis && (p[k] < cellMin[k] - pad || p[k] > cellMax[k] + pad)) return false;
    return true;
  };
  DBox found;
  // 1. Vertices inside the cell (exact).
  for (int i = 0; i < 3; ++i)
    if (insideClosed(cell, i == 0 ? a : i == 1 ? b : c)) found.extend(v[i]);
  // 2. Edges through the cell's faces. da, db: one rounding each; t = da / (da - db) with
  //    opposite signs has a relative error of a few units in the last place, and the point
  //    an absolute error of a few ulps of the magnitude.
  for (int i = 0; i < 3; ++i) {
    const DVec& p = v[i];
    const DVec& q = v[(i + 1) % 3];
    for (int axis = 0; axis < 3; ++axis)
      for (const double s : {cellMin[axis], cellMax[axis]}) {
        const double dp = p[axis] - s, dq = q[axis] - s;
        if (!((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0))) continue;
        const double t = dp / (dp - dq);
        DVec x = p + t * (q - p);
        x[axis] = s;
        if (nearCell(x, axis)) found.extend(x);
      }
  }
  // 3. The cell's edges through the triangle: the edge along axis `along` at (X, Y) on the
  //    other two axes meets the triangle's plane at along = c0 + N / W (barycentric weights of
  //    (X, Y) in the triangle's projection). With edge-function errors bounded by errW, the
  //    true value lies in the interval of (N +- errN) / (W -+ errW); where that is not
  //    decidable (W within its error of 0) the whole range is kept.
  for (int along = 0; along < 3; ++along) {
    const int x = (along + 1) % 3, y = (along + 2) % 3;
    // A triangle parallel to `along` (flat in x or y) meets these edges only where other
    // cases already put points (its vertices, its edges through faces, or other edges).
    if (triBox.min[x] == triBox.max[x] || triBox.min[y] == triBox.max[y]) continue;
    const double span = std::max(double(triBox.max[x]) - triBox.min[x], double(triBox.max[y]) - triBox.min[y]);
    const double errBound = 16.0 * kUnitRoundoff * span * span;
    double w = edgeFunction(v[0], v[1], v[2][x], v[2][y], x, y);
    double errW = errBound;
    if (std::fabs(w) <= errBound && edgeFunctionIsExact(v[0], v[1], v[2][x], v[2][y], x, y)) {
      if (w == 0.0) continue;   // exactly parallel to `along` (e.g. the plane z = y for x): as above
      errW = 0.0;
    }
    const double sign = w < 0.0 ? -1.0 : 1.0;
    w *= sign;
    const double d1 = v[1][along] - v[0][along], d2 = v[2][along] - v[0][along];
    for (const float X : {cell.min[x], cell.max[x]})
      for (const float Y : {cell.min[y], cell.max[y]}) {
        // Only corners strictly inside the triangle's box on both axes: a point of the triangle
        // on a face of its box is a vertex or on an edge lying in that face, found above.
        if (!(X > triBox.min[x] && X < triBox.max[x] && Y > triBox.min[y] && Y < triBox.max[y])) continue;
        // Outside when an edge function is below -errBound, or negative and exact.
        auto outside = [&](const DVec& p, const DVec& q, double value) {
          return value < -errBound || (value < 0.0 && edgeFunctionIsExact(p, q, X, Y, x, y));
        };
        const double w0 = sign * edgeFunction(v[1], v[2], X, Y, x, y);
        if (outside(v[1], v[2], w0)) continue;
        const double w1 = sign * edgeFunction(v[2], v[0], X, Y, x, y);
        if (outside(v[2], v[0], w1)) continue;
        const double w2 = sign * edgeFunction(v[0], v[1], X, Y, x, y);
        if (outside(v[0], v[1], w2)) continue;
        double lo = triBox.min[along], hi = triBox.max[along];
        if (w > errW) {
          const double n = w1 * d1 + w2 * d2;
          const double errN = errBound * (std::fabs(d1) + std::fabs(d2)) + 4.0 * kUnitRoundoff * std::fabs(n);
          const double q1 = (n - errN) / (w - errW), q2 = (n - errN) / (w + errW);
          const double q3 = (n + errN) / (w - errW), q4 = (n + errN) / (w + errW);
          lo = std::max(lo, v[0][along] + std::min({q1, q2, q3, q4}) - pad);
          hi = std::min(hi, v[0][along] + std::max({q1, q2, q3, q4}) + pad);
        }
        lo = std::max(lo, cellMin[along] - pad);
        hi = std::min(hi, cellMax[along] + pad);
        if (lo > hi) continue;
        DVec p;
        p[x] = X;
        p[y] = Y;
        p[along] = lo;
        found.extend(p);
        p[along] = hi;
        found.extend(p);
      }
  }
  if (!(found.min.x <= found.max.x)) return Bounds{};
  Bounds box;
  for (int k = 0; k < 3; ++k) {
    box.min[k] = roundDown(found.min[k] - pad);
    box.max[k] = roundUp(found.max[k] + pad);
  }
  box = intersect(box, limit);
  return box.empty() ? Bounds{} : box;
}

void PresplitScratch::release() {
  priority = {};
  splits = {};
  firstSlot = {};
  slots = {};
  refs = {};
}

std::span<const SplitRef> presplitTriangles(const TriangleMesh& mesh, float budget, PresplitScratch& scratch) {
  const uint32_t n = mesh.triangleCount();
  Bounds meshBox;
  for (const glm::vec3& p : mesh.positions) meshBox.extend(p);   // a superset of the triangles' box
  const Grid grid(meshBox);
  const double meshArea = std::max(halfArea(meshBox), std::numeric_limits<double>::min());
  // 1. Priorities.
  std::array<double, kGridBits> gridWeight;   // 2^-depth of a plane of each level
  for (int level = 0; level < kGridBits; ++level) gridWeight[level] = std::ldexp(1.0, level - kGridBits);
  scratch.priority.resize(n);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, kGrain), [&](const auto& r) {
    for (uint32_t t = r.begin(); t < r.end(); ++t) {
      float p = 0.0f;
      if (!mesh.degenerate[t]) {
        const glm::vec3 a = mesh.vertex(t, 0), b = mesh.vertex(t, 1), c = mesh.vertex(t, 2);
        const Bounds box = triangleBox(a, b, c);
        const GridPlane plane = grid.coarsestPlane(box);
        const double area = halfArea(box);
        if (plane.axis >= 0 && area > 0.0)
          p = static_cast<float>(std::sqrt(std::sqrt(area / meshArea * gridWeight[plane.level])));
      }
      scratch.priority[t] = std::isfinite(p) ? p : 0.0f;   // boxes too large for float areas: not split
    }
  });
  // 2. Splits per triangle and their slots.
  const auto budgetRefs = static_cast<uint64_t>(double(budget) * double(n));
  const float scale = splitScale(scratch.priority, budgetRefs);
  scratch.splits.resize(n);
  scratch.firstSlot.resize(size_t(n) + 1);
  uint64_t slots = 0;
  for (uint32_t t = 0; t < n; ++t) {
    const auto s = static_cast<uint32_t>(static_cast<int32_t>(std::min(scale * scratch.priority[t], float(kMaxSplitsPerTriangle))));
    scratch.splits[t] = s;
    scratch.firstSlot[t] = static_cast<uint32_t>(slots);
    slots += s + 1;
  }
  if (slots >= (uint64_t(1) << 31)) throw std::length_error("presplitTriangles: too many references");
  scratch.firstSlot[n] = static_cast<uint32_t>(slots);
  // 3. Split; a triangle writes at most splits + 1 references into its slots.
  scratch.slots.resize(slots);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, kGrain), [&](const auto& r) {
    for (uint32_t t = r.begin(); t < r.end(); ++t) {
      const glm::vec3 a = mesh.vertex(t, 0), b = mesh.vertex(t, 1), c = mesh.vertex(t, 2);
      SplitRef* out = &scratch.slots[scratch.firstSlot[t]];
      const Bounds box = triangleBox(a, b, c);
      if (scratch.splits[t] == 0) {
        *out = {box.min, t, box.max, 0u};
        scratch.splits[t] = 1;
      } else {
        scratch.splits[t] = TriangleSplitter(grid, a, b, c, t, out).run(box, scratch.splits[t]);
      }
    }
  });
  // Splits that found no plane leave slots unused: pack the references.
  uint64_t written = 0;
  for (uint32_t t = 0; t < n; ++t) written += scratch.splits[t];
  if (written == slots) {
    std::swap(scratch.refs, scratch.slots);
    return scratch.refs;
  }
  scratch.refs.resize(written);
  uint32_t next = 0;
  for (uint32_t t = 0; t < n; ++t) {
    std::copy_n(&scratch.slots[scratch.firstSlot[t]], scratch.splits[t], &scratch.refs[next]);
    next += scratch.splits[t];
  }
  return scratch.refs;
}

}  // namespace pa::bvh_detail
