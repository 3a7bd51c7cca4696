#pragma once
// Finiteness of vectors, which every check of untrusted or computed geometry asks.
#include <cmath>

#include <glm/vec3.hpp>

namespace pa {

/// True when every component of v is finite (no NaN, no infinity).
inline bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace pa
