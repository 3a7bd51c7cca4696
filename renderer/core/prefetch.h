#pragma once
// Cache hints for pixel buffers written in blocks across rows: each block row is a short run
// of a long row-major array, which the hardware prefetchers do not foresee; a store that
// misses the cache then holds up the stores of the shading code that follows it.
#include <cstdint>
#include <span>

namespace pa {

/// Asks for the cache lines of `elements` ahead of writing them (a hint: no effect on results).
template <class T>
void prefetchForWrite(std::span<const T> elements) {
  if (elements.empty()) return;
  constexpr uintptr_t kLine = 64;
  const uintptr_t first = reinterpret_cast<uintptr_t>(elements.data()) & ~(kLine - 1);
  const uintptr_t last = reinterpret_cast<uintptr_t>(elements.data() + elements.size()) - 1;
  for (uintptr_t line = first; line <= last; line += kLine) __builtin_prefetch(reinterpret_cast<const void*>(line), 1);
}

}  // namespace pa
