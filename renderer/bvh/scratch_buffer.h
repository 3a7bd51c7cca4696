#pragma once
// Reusable, uninitialised build memory. A BVH build touches every byte of its scratch arrays
// once; allocating them afresh per build makes each build page-fault them in again (glibc hands
// large blocks back to the OS), which cost as much as the build itself on small meshes. A
// ScratchBuffer keeps its block between builds and only grows.
#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>

#include <sys/mman.h>

namespace pa::bvh_detail {

/// Grow-only block of uninitialised memory for trivially copyable build-time arrays.
class ScratchBuffer {
 public:
  ScratchBuffer() = default;
  ~ScratchBuffer() { std::free(data_); }
  ScratchBuffer(const ScratchBuffer&) = delete;
  ScratchBuffer& operator=(const ScratchBuffer&) = delete;
  ScratchBuffer(ScratchBuffer&& o) noexcept : data_(o.data_), bytes_(o.bytes_) { o.data_ = nullptr, o.bytes_ = 0; }
  ScratchBuffer& operator=(ScratchBuffer&& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(bytes_, o.bytes_);
    return *this;
  }

  /// Room for count T (contents unspecified: earlier contents are not kept when it grows).
  template <typename T>
  T* array(size_t count) {
    static_assert(std::is_trivially_copyable_v<T> && alignof(T) <= 64);
    reserveBytes(std::max<size_t>(count, 1) * sizeof(T));
    return static_cast<T*>(data_);
  }

  /// Frees the block.
  void release() {
    std::free(data_);
    data_ = nullptr;
    bytes_ = 0;
  }

  /// Bytes held.
  size_t capacityBytes() const { return bytes_; }

 private:
  void reserveBytes(size_t bytes) {
    if (bytes <= bytes_) return;
    // Large blocks are 2 MiB aligned and marked for transparent huge pages (fewer page faults
    // on the first build); small ones are cache-line aligned.
    constexpr size_t kHuge = size_t(2) << 20;
    const bool huge = bytes >= kHuge;
    const size_t alignment = huge ? kHuge : 64;
    const size_t rounded = (bytes + alignment - 1) / alignment * alignment;
    release();
    data_ = std::aligned_alloc(alignment, rounded);
    if (data_ == nullptr) throw std::bad_alloc();
    bytes_ = rounded;
    if (huge) madvise(data_, rounded, MADV_HUGEPAGE);   // a hint; failure is harmless
  }

  void* data_ = nullptr;
  size_t bytes_ = 0;
};

}  // namespace pa::bvh_detail
