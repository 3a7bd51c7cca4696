#pragma once
// Points in a uniform grid of cells, and snapping nearly equal points onto one representative
// (internal to q3_bsp).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace q3 {

/// Points bucketed in cubic cells of one size: per cell a linked list through flat arrays,
/// cells found through an open-addressing table (no allocation per cell).
class PointCells {
 public:
  using Cell = std::array<int64_t, 3>;
  static constexpr uint32_t kNone = ~0u;

  /// `cellSize` > 0, world units; room for `expectedPoints` without regrowing.
  explicit PointCells(float cellSize, size_t expectedPoints = 0) : cell_(cellSize) {
    points_.reserve(expectedPoints);
    next_.reserve(expectedPoints);
    keys_.assign(std::bit_ceil(std::max<size_t>(64, 2 * expectedPoints)), 0);
    heads_.assign(keys_.size(), kNone);
  }

  /// The cell holding world point p.
  Cell cellOf(const glm::vec3& p) const {
    Cell c;
    for (int k = 0; k < 3; ++k) {
      const float q = p[k] / cell_;  // NaN and overflow land in the outermost cells
      c[k] = static_cast<int64_t>(q >= -1e15f && q <= 1e15f ? std::floor(q) : (q > 0 ? 1e15f : -1e15f));
    }
    return c;
  }
  /// Adds p under `tag` (points of different tags never meet); returns its id.
  uint32_t add(const glm::vec3& p, int32_t tag = 0) {
    if (2 * (cellCount_ + 1) > keys_.size()) grow();
    const uint64_t key = cellKey(cellOf(p), tag);
    size_t slot = find(key);
    if (heads_[slot] == kNone) {
      keys_[slot] = key;
      ++cellCount_;
    }
    next_.push_back(heads_[slot]);
    heads_[slot] = static_cast<uint32_t>(points_.size());
    points_.push_back(p);
    return heads_[slot];
  }
  /// Calls visit(id) for every point of `tag` in the cells from lo to hi (inclusive).
  template <class Visit>
  void forEachIn(int32_t tag, const Cell& lo, const Cell& hi, Visit&& visit) const {
    if (points_.empty()) return;
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t z = lo[2]; z <= hi[2]; ++z)
          for (uint32_t id = heads_[find(cellKey({x, y, z}, tag))]; id != kNone; id = next_[id]) visit(id);
  }
  /// Point number `id`.
  const glm::vec3& point(uint32_t id) const { return points_[id]; }
  /// Number of points added.
  size_t size() const { return points_.size(); }

 private:
  static uint64_t cellKey(const Cell& c, int32_t tag) {
    uint64_t h = 0x9e3779b97f4a7c15ull ^ static_cast<uint32_t>(tag);
    for (int64_t v : c) {
      h ^= static_cast<uint64_t>(v) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
      h *= 0xff51afd7ed558ccdull;
      h ^= h >> 33;
    }
    return h;
  }
  /// The slot holding `key`, or the empty slot where it would go.
  size_t find(uint64_t key) const {
    const size_t mask = keys_.size() - 1;
    for (size_t slot = key & mask;; slot = (slot + 1) & mask)
      if (heads_[slot] == kNone || keys_[slot] == key) return slot;
  }
  void grow() {
    std::vector<uint64_t> oldKeys = std::move(keys_);
    std::vector<uint32_t> oldHeads = std::move(heads_);
    const size_t capacity = std::max<size_t>(64, 2 * oldKeys.size());
    keys_.assign(capacity, 0);
    heads_.assign(capacity, kNone);
    for (size_t s = 0; s < oldKeys.size(); ++s)
      if (oldHeads[s] != kNone) {
        const size_t slot = find(oldKeys[s]);
        keys_[slot] = oldKeys[s];
        heads_[slot] = oldHeads[s];
      }
  }

  float cell_;
  std::vector<uint64_t> keys_;   ///< per table slot: cell key
  std::vector<uint32_t> heads_;  ///< per table slot: newest point of the cell, kNone = empty slot
  size_t cellCount_ = 0;
  std::vector<glm::vec3> points_;
  std::vector<uint32_t> next_;   ///< per point: the next older point of its cell
};

/// Snaps a point onto the oldest representative within `distance` of it (else keeps it as a
/// new representative), so that points written with float noise (15.9999943 against 16) become
/// bit-identical. Representatives are pairwise more than `distance` apart, and equal points
/// always get the same answer.
class PointWelder {
 public:
  /// `distance` > 0: points at most this far apart are merged; `expectedPoints` sizes the table.
  explicit PointWelder(float distance, size_t expectedPoints = 0)
      : distance_(distance), cells_(16 * distance, expectedPoints) {}

  /// The representative of `p`.
  glm::vec3 weld(const glm::vec3& p) {
    // Cells are 16 * distance wide: the box of points within `distance` mostly lies in one.
    uint32_t oldest = PointCells::kNone;
    cells_.forEachIn(0, cells_.cellOf(p - distance_), cells_.cellOf(p + distance_), [&](uint32_t id) {
      if (id < oldest && glm::distance(p, cells_.point(id)) <= distance_) oldest = id;
    });
    if (oldest != PointCells::kNone) return cells_.point(oldest);
    cells_.add(p);
    return p;
  }

 private:
  float distance_;
  PointCells cells_;
};

}  // namespace q3
