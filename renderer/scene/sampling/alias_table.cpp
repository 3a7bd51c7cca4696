#include "renderer/scene/sampling/alias_table.h"

#include <algorithm>
#include <cmath>

namespace pa::sampling {

AliasTable::AliasTable(std::span<const double> weights) { rebuild(weights); }

void AliasTable::rebuild(std::span<const double> weights) {
  const size_t n = weights.size();
  total_ = 0.0;
  threshold_.clear();
  alias_.clear();
  pdf_.clear();
  std::vector<double>& w = weights_;
  w.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const double x = weights[i];
    w[i] = (std::isfinite(x) && x > 0.0) ? x : 0.0;
    total_ += w[i];
  }
  if (!(total_ > 0.0) || !std::isfinite(total_)) {
    total_ = 0.0;
    return;
  }
  pdf_.resize(n);
  threshold_.assign(n, 1.0f);
  alias_.resize(n);
  std::vector<double>& scaled = scaled_;
  scaled.resize(n);
  std::vector<uint32_t>& small = small_;
  std::vector<uint32_t>& large = large_;
  small.clear();
  large.clear();
  for (size_t i = 0; i < n; ++i) {
    pdf_[i] = static_cast<float>(w[i] / total_);
    scaled[i] = w[i] / total_ * static_cast<double>(n);
    alias_[i] = static_cast<uint32_t>(i);
    (scaled[i] < 1.0 ? small : large).push_back(static_cast<uint32_t>(i));
  }
  while (!small.empty() && !large.empty()) {
    const uint32_t s = small.back();
    small.pop_back();
    const uint32_t l = large.back();
    threshold_[s] = static_cast<float>(scaled[s]);
    alias_[s] = l;
    scaled[l] = (scaled[l] + scaled[s]) - 1.0;
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // Leftovers are 1 up to rounding: keep their own entry unless it has no weight at all.
  const auto firstPositive = static_cast<uint32_t>(
      std::find_if(w.begin(), w.end(), [](double x) { return x > 0.0; }) - w.begin());
  for (uint32_t i : small) {
    threshold_[i] = w[i] > 0.0 ? 1.0f : 0.0f;
    alias_[i] = w[i] > 0.0 ? i : firstPositive;
  }
  for (uint32_t i : large) threshold_[i] = 1.0f;
}

uint32_t AliasTable::sample(float u) const {
  const uint32_t n = size();
  const double scaled = static_cast<double>(u) * n;
  const uint32_t bucket = std::min(static_cast<uint32_t>(scaled), n - 1);
  const auto frac = static_cast<float>(scaled - bucket);
  return frac < threshold_[bucket] ? bucket : alias_[bucket];
}

}  // namespace pa::sampling
