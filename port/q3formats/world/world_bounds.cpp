// WorldBounds helpers.
#include <glm/common.hpp>

#include "port/q3formats/world/world_scene.h"

namespace q3 {

void WorldBounds::extend(const glm::vec3& p) {
  mins = glm::min(mins, p);
  maxs = glm::max(maxs, p);
}

}  // namespace q3
