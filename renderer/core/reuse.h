#pragma once
// Memory that is refilled every frame (dynamic meshes, their BVHs, the committed scene): grown
// geometrically, so that arrays whose size varies from frame to frame stop allocating once they
// have reached their largest size, instead of reallocating to each new exact size.
#include <algorithm>
#include <cstddef>
#include <iterator>

namespace pa {

/// Makes room for n elements in v (a std::vector), at least doubling its capacity when it grows.
template <class Vector>
void reserveGeometric(Vector& v, size_t n) {
  if (n > v.capacity()) v.reserve(std::max(n, 2 * v.capacity()));
}

/// v.assign(first, last) without exact-size reallocation (see reserveGeometric).
template <class Vector, class Iterator>
void assignReusing(Vector& v, Iterator first, Iterator last) {
  reserveGeometric(v, static_cast<size_t>(std::distance(first, last)));
  v.assign(first, last);
}

/// v.resize(n) without exact-size reallocation (see reserveGeometric).
template <class Vector>
void resizeReusing(Vector& v, size_t n) {
  reserveGeometric(v, n);
  v.resize(n);
}

}  // namespace pa
