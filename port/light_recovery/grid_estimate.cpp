// estimateLightsFromGrid: light positions from the light grid's directions (line voting and
// least squares), light values from its directed magnitudes (q3map2 inverse-square falloff).
#include "port/light_recovery/grid_estimate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "port/q3formats/bsp/light_grid.h"
#include "port/q3formats/world/world_lights.h"

namespace pa::recovery {

using namespace q3;
namespace {

constexpr float kMinLightDistance = 16.0f;   // q3map2 clamps the distance of point lights here
constexpr float kSaturated = 254.0f;         // a clamped byte says nothing about the magnitude

/// A grid point that votes: a half-line from its position towards its dominant light.
struct Line {
  glm::vec3 origin;
  glm::vec3 direction;   // unit
  glm::vec3 directed;    // directed colour, 0..255 per channel
  float length;          // the light cannot be farther than this
  int owner = -1;        // index of the estimated light it was assigned to
};

float maxChannel(const glm::vec3& c) { return std::max({c.r, c.g, c.b}); }

bool finiteVec(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// The accumulator: a box of voxels holding (blurred) line counts.
class VoteVolume {
 public:
  VoteVolume(glm::vec3 mins, glm::vec3 maxs, float voxel) : mins_(mins), voxel_(voxel) {
    for (int k = 0; k < 3; ++k) dims_[k] = std::max(1, int(std::ceil((maxs[k] - mins[k]) / voxel)) + 1);
    votes_.assign(size_t(dims_[0]) * size_t(dims_[1]) * size_t(dims_[2]), 0.0f);
  }

  /// Adds one vote to every voxel the segment [origin, origin + direction * length] crosses.
  void addLine(const Line& line) {
    const float step = 0.5f * voxel_;
    size_t last = SIZE_MAX;
    for (float t = 0.5f * voxel_; t <= line.length; t += step) {
      const size_t index = voxelAt(line.origin + t * line.direction);
      if (index == SIZE_MAX) break;   // left the box: nothing beyond
      if (index != last) votes_[index] += 1.0f;
      last = index;
    }
  }

  /// Separable 3x3x3 box sum: lines that miss each other by a voxel still meet (a line
  /// crossing the box adds about 3 to the sum at its centre).
  void blur() {
    std::vector<float> tmp(votes_.size());
    const std::array<size_t, 3> stride{1, size_t(dims_[0]), size_t(dims_[0]) * size_t(dims_[1])};
    for (int axis = 0; axis < 3; ++axis) {
      size_t i = 0;
      for (int z = 0; z < dims_[2]; ++z)
        for (int y = 0; y < dims_[1]; ++y)
          for (int x = 0; x < dims_[0]; ++x, ++i) {
            const int c = axis == 0 ? x : axis == 1 ? y : z;
            const float prev = c > 0 ? votes_[i - stride[axis]] : 0.0f;
            const float next = c + 1 < dims_[axis] ? votes_[i + stride[axis]] : 0.0f;
            tmp[i] = prev + votes_[i] + next;
          }
      votes_.swap(tmp);
    }
  }

  /// Voxels that are the strict maximum of their 26 neighbours (ties: first in memory order)
  /// with at least minVotes, strongest first.
  std::vector<std::pair<float, glm::vec3>> peaks(float minVotes) const {
    std::vector<std::pair<float, glm::vec3>> out;
    for (int z = 0; z < dims_[2]; ++z)
      for (int y = 0; y < dims_[1]; ++y)
        for (int x = 0; x < dims_[0]; ++x) {
          const size_t i = index(x, y, z);
          const float v = votes_[i];
          if (v < minVotes || !isLocalMaximum(x, y, z, i, v)) continue;
          out.emplace_back(v, mins_ + (glm::vec3(x, y, z) + 0.5f) * voxel_);
        }
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    return out;
  }

 private:
  glm::vec3 mins_;
  float voxel_;
  std::array<int, 3> dims_{};
  std::vector<float> votes_;

  size_t index(int x, int y, int z) const { return (size_t(z) * size_t(dims_[1]) + size_t(y)) * size_t(dims_[0]) + size_t(x); }
  size_t voxelAt(const glm::vec3& p) const {
    const glm::vec3 f = (p - mins_) / voxel_;
    if (!(f.x >= 0.0f && f.y >= 0.0f && f.z >= 0.0f)) return SIZE_MAX;
    const int x = int(f.x), y = int(f.y), z = int(f.z);
    if (x >= dims_[0] || y >= dims_[1] || z >= dims_[2]) return SIZE_MAX;
    return index(x, y, z);
  }
  bool isLocalMaximum(int x, int y, int z, size_t i, float v) const {
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy, nz = z + dz;
          if ((dx | dy | dz) == 0 || nx < 0 || ny < 0 || nz < 0 || nx >= dims_[0] || ny >= dims_[1] || nz >= dims_[2])
            continue;
          const size_t j = index(nx, ny, nz);
          const float w = votes_[j];
          if (w > v || (w == v && j < i)) return false;
        }
    return true;
  }
};

/// Signed distance along the line and distance from it of point p.
struct LineDistance {
  float along;
  float across;
};
LineDistance distanceToLine(const Line& line, const glm::vec3& p) {
  const glm::vec3 d = p - line.origin;
  const float along = glm::dot(d, line.direction);
  return {along, glm::length(d - along * line.direction)};
}

bool explained(const glm::vec3& p, const KnownLighting& known, float radius) {
  for (const auto& [light, value] : known.pointLights)
    if (glm::length(light - p) < radius) return true;
  for (const auto& [centre, r] : known.emitters)
    if (glm::length(centre - p) < radius + r) return true;
  return false;
}

/// True when the line points at one of the scene's own point lights.
bool passesKnownLight(const Line& line, const KnownLighting& known, const LightEstimateOptions& o) {
  for (const auto& [light, value] : known.pointLights) {
    const LineDistance d = distanceToLine(line, light);
    if (d.along > 0.0f && d.along <= line.length && d.across <= o.lineTolerance + o.angularTolerance * d.along)
      return true;
  }
  return false;
}

/// Reads the grid into voting lines; empty for an inconsistent grid.
std::vector<Line> votingLines(const WorldLightGrid& grid, const KnownLighting& known, const LightEstimateOptions& o,
                              LightEstimateStats& stats) {
  std::vector<Line> lines;
  const auto& n = grid.counts;
  if (n[0] <= 0 || n[1] <= 0 || n[2] <= 0 || !finiteVec(grid.origin) || !finiteVec(grid.cellSize) ||
      !(std::min({grid.cellSize.x, grid.cellSize.y, grid.cellSize.z}) > 0.0f))
    return lines;
  const size_t count = size_t(n[0]) * size_t(n[1]) * size_t(n[2]);
  if (count != grid.samples.size()) return lines;
  stats.gridPoints = count;
  for (size_t i = 0; i < count; ++i) {
    const auto& s = grid.samples[i];
    const glm::vec3 directed(s[3], s[4], s[5]);
    const float magnitude = maxChannel(directed);
    if (magnitude < o.minDirected) continue;
    const glm::vec3 direction = lightGridDirection(s[6], s[7]);
    bool sun = false;
    for (const glm::vec3& towardSun : known.towardSuns) sun = sun || glm::dot(direction, towardSun) > o.sunAngleCos;
    if (sun) continue;
    const size_t x = i % size_t(n[0]), y = (i / size_t(n[0])) % size_t(n[1]), z = i / (size_t(n[0]) * size_t(n[1]));
    Line line;
    line.origin = grid.origin + glm::vec3(float(x), float(y), float(z)) * grid.cellSize;
    line.direction = direction;
    line.directed = directed;
    // directed = V * pointScale / d^2 with V <= maxLightValue bounds d.
    line.length = std::min(o.maxLineLength, std::sqrt(o.maxLightValue * kQ3mapPointScale / magnitude));
    if (!passesKnownLight(line, known, o)) lines.push_back(line);
  }
  return lines;
}

/// Least-squares point nearest to the lines (weights ~ 1 / distance^2: direction bytes err in angle).
bool nearestPoint(const std::vector<Line>& lines, const std::vector<size_t>& members, const glm::vec3& guess,
                  glm::vec3& out) {
  glm::dmat3 a(0.0);
  glm::dvec3 b(0.0);
  for (size_t m : members) {
    const Line& l = lines[m];
    const float t = std::max(32.0f, distanceToLine(l, guess).along);
    const double w = double(maxChannel(l.directed)) / (double(t) * double(t));
    const glm::dvec3 d(l.direction);
    const glm::dmat3 projector = glm::dmat3(1.0) - glm::outerProduct(d, d);
    a += w * projector;
    b += w * (projector * glm::dvec3(l.origin));
  }
  const double det = glm::determinant(a);
  if (!(std::abs(det) > 1e-18)) return false;
  const glm::dvec3 p = glm::inverse(a) * b;
  out = glm::vec3(p);
  return finiteVec(out);
}

/// Coarse bins listing the lines that cross them, so that the lines near a point are found
/// without visiting every line. Bins are at least as wide as the largest line tolerance, so
/// the lines within tolerance of p all cross one of the 27 bins around p's bin.
class LineIndex {
 public:
  LineIndex(const std::vector<Line>& lines, glm::vec3 mins, glm::vec3 maxs, float binSize)
      : mins_(mins), bin_(binSize), seen_(lines.size(), UINT32_MAX) {
    for (int k = 0; k < 3; ++k) dims_[k] = std::max(1, int(std::ceil((maxs[k] - mins[k]) / binSize)) + 1);
    // Compressed rows: count the lines per bin, then fill.
    start_.assign(size_t(dims_[0]) * size_t(dims_[1]) * size_t(dims_[2]) + 1, 0);
    for (size_t i = 0; i < lines.size(); ++i) forBinsOf(lines[i], [&](size_t b) { ++start_[b + 1]; });
    for (size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
    entries_.resize(start_.back());
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < lines.size(); ++i) forBinsOf(lines[i], [&](size_t b) { entries_[fill[b]++] = uint32_t(i); });
  }

  /// Calls f(line index) once for every line crossing a bin next to p.
  template <typename F>
  void forLinesNear(const glm::vec3& p, F&& f) {
    ++stamp_;
    const glm::vec3 c = glm::floor((p - mins_) / bin_);
    if (!finiteVec(c)) return;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const float x = c.x + float(dx), y = c.y + float(dy), z = c.z + float(dz);
          if (x < 0 || y < 0 || z < 0 || x >= float(dims_[0]) || y >= float(dims_[1]) || z >= float(dims_[2])) continue;
          const size_t b = (size_t(z) * size_t(dims_[1]) + size_t(y)) * size_t(dims_[0]) + size_t(x);
          for (uint32_t e = start_[b]; e < start_[b + 1]; ++e) {
            const uint32_t line = entries_[e];
            if (seen_[line] == stamp_) continue;
            seen_[line] = stamp_;
            f(size_t(line));
          }
        }
  }

 private:
  glm::vec3 mins_;
  float bin_;
  std::array<int, 3> dims_{};
  std::vector<uint32_t> start_;     // bin b lists entries_[start_[b], start_[b + 1])
  std::vector<uint32_t> entries_;
  std::vector<uint32_t> seen_;
  uint32_t stamp_ = 0;

  /// Calls f(bin) once for each bin the line crosses (sampled every half bin).
  template <typename F>
  void forBinsOf(const Line& line, F&& f) const {
    size_t last = SIZE_MAX;
    for (float t = 0.0f; t <= line.length + 0.5f * bin_; t += 0.5f * bin_) {
      const size_t b = binAt(line.origin + std::min(t, line.length) * line.direction);
      if (b == SIZE_MAX) break;
      if (b != last) f(b);
      last = b;
    }
  }

  size_t binAt(const glm::vec3& p) const {
    const glm::vec3 f = (p - mins_) / bin_;
    if (!(f.x >= 0.0f && f.y >= 0.0f && f.z >= 0.0f)) return SIZE_MAX;
    const int x = int(f.x), y = int(f.y), z = int(f.z);
    if (x >= dims_[0] || y >= dims_[1] || z >= dims_[2]) return SIZE_MAX;
    return (size_t(z) * size_t(dims_[1]) + size_t(y)) * size_t(dims_[0]) + size_t(x);
  }
};

/// Unowned lines passing close to p, in front of their grid point and within their length.
std::vector<size_t> linesThrough(const std::vector<Line>& lines, LineIndex& index, const glm::vec3& p,
                                 const LightEstimateOptions& o) {
  std::vector<size_t> members;
  index.forLinesNear(p, [&](size_t i) {
    if (lines[i].owner >= 0) return;
    const LineDistance d = distanceToLine(lines[i], p);
    if (d.along <= 0.0f || d.along > lines[i].length + o.lineTolerance) return;
    if (d.across <= o.lineTolerance + o.angularTolerance * d.along) members.push_back(i);
  });
  std::sort(members.begin(), members.end());
  return members;
}

/// Lines of `members` whose direction the lights in `others` (marked true in `use`) do not
/// explain: q3map2's blend of those lights would point elsewhere.
size_t unexplainedLines(const std::vector<Line>& lines, const std::vector<size_t>& members,
                        const std::vector<WorldLight>& others, const std::vector<bool>& use, size_t self,
                        const LightEstimateOptions& o) {
  size_t count = 0;
  for (size_t m : members) {
    glm::vec3 blend(0.0f);
    for (size_t j = 0; j < others.size(); ++j) {
      if (j == self || !use[j]) continue;
      const glm::vec3 toLight = others[j].position - lines[m].origin;
      const float d = std::max(kMinLightDistance, glm::length(toLight));
      blend += (others[j].quakeIntensity * glm::length(others[j].color) / (d * d * d)) * toLight;
    }
    const float len = glm::length(blend);
    if (!(len > 0.0f) || glm::dot(blend / len, lines[m].direction) < o.blendAngleCos) ++count;
  }
  return count;
}

/// Keeps the candidates that explain lines no other light explains. Peaks also form where
/// lines that q3map2 blended from two lights cross; such a candidate's lines are explained by
/// the blend of the others. Forward (most lines first, against those kept so far), then
/// backward (fewest lines first, against all others kept). Occlusion is ignored, which only
/// ever keeps a candidate (a wrong blend explains nothing).
void keepExplainingLights(const std::vector<Line>& lines, std::vector<WorldLight>& lights,
                          std::vector<std::vector<size_t>>& memberLists, const KnownLighting& known,
                          const LightEstimateOptions& o) {
  const size_t candidates = lights.size();
  std::vector<size_t> order(candidates);
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return memberLists[a].size() > memberLists[b].size(); });
  // The scene's own point lights take part in every blend.
  std::vector<WorldLight> all = lights;
  for (const auto& [position, value] : known.pointLights) {
    WorldLight l;
    l.position = position;
    l.quakeIntensity = value;
    all.push_back(l);
  }
  std::vector<bool> kept(all.size(), true);
  for (size_t c = 0; c < candidates; ++c) kept[c] = false;
  for (size_t c : order) kept[c] = unexplainedLines(lines, memberLists[c], all, kept, c, o) >= o.minLines;
  for (auto it = order.rbegin(); it != order.rend(); ++it)
    if (kept[*it]) kept[*it] = unexplainedLines(lines, memberLists[*it], all, kept, *it, o) >= o.minLines;
  std::vector<WorldLight> out;
  for (size_t i : order)
    if (kept[i]) out.push_back(lights[i]);
  lights.swap(out);
}

/// Least-squares slope of log(directed) over log(distance) for the unsaturated lines: -2 for
/// an inverse-square point light; NaN when the distances span too little.
float falloffSlope(const std::vector<Line>& lines, const std::vector<size_t>& members, const glm::vec3& p) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
  float dMin = 1e30f, dMax = 0.0f;
  for (size_t m : members) {
    const float magnitude = maxChannel(lines[m].directed);
    if (magnitude >= kSaturated) continue;
    const float d = std::max(kMinLightDistance, glm::length(p - lines[m].origin));
    dMin = std::min(dMin, d);
    dMax = std::max(dMax, d);
    const double x = std::log(double(d)), y = std::log(double(magnitude));
    sx += x; sy += y; sxx += x * x; sxy += x * y; n += 1;
  }
  const double denominator = n * sxx - sx * sx;
  if (n < 3 || dMax < 1.5f * dMin || !(denominator > 0.0)) return std::numeric_limits<float>::quiet_NaN();
  return float((n * sxy - sx * sy) / denominator);
}

/// Smallest voxel edge >= options.voxelSize whose box fits the voxel budget (0 if none does).
float voxelSizeFor(const glm::vec3& extent, const LightEstimateOptions& o) {
  if (!finiteVec(extent)) return 0.0f;
  const double budget = double(std::max<size_t>(o.maxVoxels, 1));
  double voxel = std::max(1.0, double(o.voxelSize));
  for (int i = 0; i < 400; ++i, voxel *= 1.25) {
    double count = 1.0;
    for (int k = 0; k < 3; ++k) count *= std::ceil(double(extent[k]) / voxel) + 1.0;
    if (count <= budget) return std::isfinite(float(voxel)) ? float(voxel) : 0.0f;
  }
  return 0.0f;
}

}  // namespace

std::vector<WorldLight> estimateLightsFromGrid(const WorldLightGrid& grid, const KnownLighting& known,
                                               const LightEstimateOptions& options, LightEstimateStats* statsOut,
                                               std::vector<WorldLight>* rejected) {
  LightEstimateStats stats;
  std::vector<WorldLight> lights;
  std::vector<Line> lines = votingLines(grid, known, options, stats);
  stats.votingLines = lines.size();
  if (lines.size() < options.minLines) {
    if (statsOut) *statsOut = stats;
    return lights;
  }

  // Accumulator over the grid's box (plus one cell), voxels grown to fit the budget.
  const glm::vec3 mins = grid.origin - grid.cellSize;
  const glm::vec3 maxs = grid.origin + glm::vec3(grid.counts[0], grid.counts[1], grid.counts[2]) * grid.cellSize;
  const float voxel = voxelSizeFor(maxs - mins, options);
  stats.voxelSize = voxel;
  if (!(voxel > 0.0f) || !std::isfinite(voxel)) {
    if (statsOut) *statsOut = stats;
    return lights;
  }
  VoteVolume votes(mins, maxs, voxel);
  for (const Line& line : lines) votes.addLine(line);
  votes.blur();
  const auto peaks = votes.peaks(options.minVotes);
  // Bins as wide as the largest tolerance a line can have (the 27 around p cover it).
  LineIndex index(lines, mins, maxs,
                  std::max(2.0f * voxel, options.lineTolerance + options.angularTolerance * options.maxLineLength));
  stats.peaks = peaks.size();

  std::vector<std::vector<size_t>> memberLists;   // per light: the lines that located it
  for (size_t p = 0; p < std::min(peaks.size(), options.maxPeaks); ++p) {
    const glm::vec3 peak = peaks[p].second;
    if (lights.size() >= options.maxLights) break;
    // Refine: gather the lines through the current estimate, move it to their nearest point.
    glm::vec3 position = peak;
    std::vector<size_t> members = linesThrough(lines, index, position, options);
    for (int iteration = 0; iteration < 3 && members.size() >= options.minLines; ++iteration) {
      glm::vec3 refined;
      if (!nearestPoint(lines, members, position, refined) || glm::length(refined - peak) > 2.0f * voxel + options.lineTolerance)
        break;
      position = refined;
      members = linesThrough(lines, index, position, options);
    }
    if (members.size() < options.minLines) continue;
    bool duplicate = false;
    for (const WorldLight& l : lights) duplicate = duplicate || glm::length(l.position - position) < 2.0f * voxel;
    if (duplicate) continue;

    // Light value: median over unsaturated lines of directed * d^2 / pointScale.
    std::vector<float> values, saturatedValues;
    glm::vec3 colorSum(0.0f);
    for (size_t m : members) {
      const Line& l = lines[m];
      const float d = std::max(kMinLightDistance, glm::length(position - l.origin));
      const float value = maxChannel(l.directed) * d * d / kQ3mapPointScale;
      if (maxChannel(l.directed) < kSaturated) {
        values.push_back(value);
        colorSum += l.directed;
      } else {
        saturatedValues.push_back(value);   // a lower bound only
      }
    }
    std::vector<float>& used = values.empty() ? saturatedValues : values;
    std::sort(used.begin(), used.end());
    const float value = used[used.size() / 2];
    const float spread = used[used.size() * 3 / 4] / std::max(1e-3f, used[used.size() / 4]);
    const float slope = falloffSlope(lines, members, position);
    const int owner = int(lights.size());
    for (size_t m : members) lines[m].owner = owner;
    if (!(value >= options.minLightValue) || !std::isfinite(value) || explained(position, known, options.explainedRadius))
      continue;
    // A point light gives consistent values along its lines and an inverse-square falloff;
    // crossings of lines towards area lights or the sky give neither.
    WorldLight light;
    light.type = WorldLightType::Point;
    light.position = position;
    const float peakColor = maxChannel(colorSum);
    light.color = peakColor > 0.0f ? colorSum / peakColor : glm::vec3(1.0f);
    light.quakeIntensity = value;
    light.intensity = pointLightIntensity(value);
    light.estimated = true;
    light.source = "light grid estimate (" + std::to_string(members.size()) + " grid points)";
    if (spread > options.maxValueSpread || !(slope < options.minFalloffSlope) ||
        (!(slope < options.pointFalloffSlope) && spread > options.looseValueSpread)) {
      if (rejected && rejected->size() < options.maxLights) {
        light.source = "light grid candidate (" + std::to_string(members.size()) + " grid points)";
        rejected->push_back(light);
      }
      continue;
    }
    lights.push_back(light);
    memberLists.push_back(std::move(members));
  }
  keepExplainingLights(lines, lights, memberLists, known, options);
  stats.lights = lights.size();
  if (statsOut) *statsOut = stats;
  return lights;
}

KnownLighting knownLightingOf(const WorldScene& scene) {
  KnownLighting known;
  for (const WorldLight& l : scene.lights) {
    if (l.estimated) continue;   // recovered earlier: not the scene's own light
    if (l.type == WorldLightType::Sun) {
      const float len = glm::length(l.direction);
      if (len > 1e-6f && std::isfinite(len)) known.towardSuns.push_back(-l.direction / len);
    } else {
      known.pointLights.emplace_back(l.position, l.quakeIntensity);
    }
  }
  for (const WorldModel& model : scene.models)
    for (const WorldMesh& mesh : model.meshes) {
      if (mesh.material >= scene.materials.size()) continue;
      const WorldMaterial& m = scene.materials[mesh.material];
      if (!(m.surfaceLight > 0.0f) || m.sky) continue;
      for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
        if (a >= mesh.positions.size() || b >= mesh.positions.size() || c >= mesh.positions.size()) continue;
        const glm::vec3 centre = (mesh.positions[a] + mesh.positions[b] + mesh.positions[c]) / 3.0f;
        const float radius = std::max({glm::length(mesh.positions[a] - centre), glm::length(mesh.positions[b] - centre),
                                       glm::length(mesh.positions[c] - centre)});
        known.emitters.emplace_back(centre, radius);
      }
    }
  return known;
}

bool lightsStripped(const std::vector<WorldLight>& lights) {
  constexpr size_t kEnoughEntityLights = 16;
  const size_t entityLights = size_t(std::count_if(lights.begin(), lights.end(), [](const WorldLight& l) {
    return l.type != WorldLightType::Sun && !l.estimated;
  }));
  return entityLights < kEnoughEntityLights;
}

}  // namespace pa::recovery
