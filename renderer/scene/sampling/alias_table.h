#pragma once
// Walker/Vose alias table: O(1) sampling of a discrete distribution.
#include <cstdint>
#include <span>
#include <vector>

namespace pa::sampling {

/// Discrete distribution proportional to non-negative weights, sampled with one uniform number.
class AliasTable {
 public:
  AliasTable() = default;
  /// Builds from weights; negative or non-finite weights count as 0. All-zero -> empty table.
  explicit AliasTable(std::span<const double> weights);
  /// The same, in place: a table rebuilt over as many weights as before allocates nothing.
  void rebuild(std::span<const double> weights);

  /// True when there is nothing to sample (no weight > 0).
  bool empty() const { return total_ <= 0.0; }
  /// Number of entries (including zero-weight ones).
  uint32_t size() const { return static_cast<uint32_t>(pdf_.size()); }
  /// Picks an entry from u in [0, 1). Must not be called on an empty table.
  uint32_t sample(float u) const;
  /// Probability of picking entry i.
  float pdf(uint32_t i) const { return i < pdf_.size() ? pdf_[i] : 0.0f; }
  /// Sum of the weights.
  double total() const { return total_; }

 private:
  std::vector<float> threshold_;   ///< Probability of keeping the bucket's own entry.
  std::vector<uint32_t> alias_;
  std::vector<float> pdf_;
  double total_ = 0.0;
  // The build's working arrays, kept for rebuilds.
  std::vector<double> weights_, scaled_;
  std::vector<uint32_t> small_, large_;
};

}  // namespace pa::sampling
