#include "port/engine_glue/entity_slots.h"

#include <glm/geometric.hpp>

namespace glue {

void EntitySlots::beginFrame() {
  previous_ = owners_;
  for (Owner& owner : owners_) owner.used = false;
  claimed_.assign(owners_.size(), 0);
}

size_t EntitySlots::claim(const EntityKey& key, const glm::vec3& origin) {
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
  if (best == owners_.size()) {   // no match: a slot that showed nothing last frame, or a new one
    for (size_t i = 0; i < owners_.size(); ++i) {
      if (claimed_[i] == 0 && (i >= previous_.size() || !previous_[i].used)) {
        best = i;
        break;
      }
    }
  }
  if (best == owners_.size()) {
    owners_.emplace_back();
    claimed_.push_back(0);
  }
  owners_[best] = Owner{true, key, origin};
  claimed_[best] = 1;
  return best;
}

}  // namespace glue
