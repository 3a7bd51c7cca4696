#include "port/engine_glue/entity_slots.h"

#include <algorithm>

#include <glm/geometric.hpp>

namespace glue {

void EntitySlots::beginFrame() {
  previous_ = owners_;
  for (Owner& owner : owners_) owner.used = false;
  claimed_.assign(owners_.size(), 0);
}

size_t EntitySlots::claim(const EntityKey& key, const glm::vec3& origin, size_t triangles) {
  size_t best = owners_.size();
  float bestDistance = kReach;
  for (size_t i = 0; i < previous_.size(); ++i) {
    if (claimed_[i] != 0 || !previous_[i].used || !(previous_[i].key == key)) continue;
    const float distance = glm::length(previous_[i].origin - origin);
    if (distance <= bestDistance) {
      bestDistance = distance;
      best = i;
    }
  }
  if (best == owners_.size()) best = freeSlotFor(key, triangles);
  if (best == owners_.size()) {
    owners_.emplace_back();
    claimed_.push_back(0);
    capacity_.push_back(0);
  }
  owners_[best] = Owner{true, key, origin};
  claimed_[best] = 1;
  capacity_[best] = std::max(capacity_[best], triangles);
  return best;
}

size_t EntitySlots::freeSlotFor(const EntityKey& key, size_t triangles) const {
  // A slot that showed nothing last frame: one that last showed the same model (its mesh has
  // that size: the update refits it), else the smallest that has held as many triangles, else
  // the largest (it grows the least); owners_.size() when none is free.
  size_t fitting = owners_.size(), largest = owners_.size();
  for (size_t i = 0; i < owners_.size(); ++i) {
    if (claimed_[i] != 0 || (i < previous_.size() && previous_[i].used)) continue;
    if (i < previous_.size() && previous_[i].key == key) return i;
    if (capacity_[i] >= triangles && (fitting == owners_.size() || capacity_[i] < capacity_[fitting])) fitting = i;
    if (largest == owners_.size() || capacity_[i] > capacity_[largest]) largest = i;
  }
  return fitting != owners_.size() ? fitting : largest;
}

}  // namespace glue
