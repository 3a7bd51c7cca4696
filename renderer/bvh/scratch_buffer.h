#pragma once
// Reusable, uninitialised build memory. A BVH build touches every byte of its scratch arrays
// once, and on the VM we measure on a 4 KiB page fault costs 13-17 us (renderer/bvh/README.md, "Memory"):
// fresh memory per build cost as much as the build itself on small meshes. A ScratchBuffer keeps
// its block between builds and only grows; blocks of kHugePagesFrom bytes or more are mapped in
// 2 MiB transparent huge pages, so a first build faults once per 2 MiB instead of per 4 KiB.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>

#include <sys/mman.h>

namespace pa::bvh_detail {

/// Grow-only block of uninitialised memory for trivially copyable build-time arrays.
class ScratchBuffer {
 public:
  /// Blocks this large are 2 MiB-aligned mappings advised for transparent huge pages.
  static constexpr size_t kHugePagesFrom = size_t(256) << 10;

  ScratchBuffer() = default;
  ~ScratchBuffer() { release(); }
  ScratchBuffer(const ScratchBuffer&) = delete;
  ScratchBuffer& operator=(const ScratchBuffer&) = delete;
  ScratchBuffer(ScratchBuffer&& o) noexcept { swap(o); }
  ScratchBuffer& operator=(ScratchBuffer&& o) noexcept {
    swap(o);
    return *this;
  }

  /// At least `bytes` bytes, 64-byte aligned (contents unspecified: not kept when it grows). A
  /// block that grows again at least doubles, so that meshes rebuilt at varying sizes (dynamic
  /// meshes in play) stop reallocating once they reach their largest.
  std::byte* reserve(size_t bytes) {
    if (bytes > bytes_) grow(bytes_ == 0 ? bytes : std::max(bytes, 2 * bytes_));
    return data_;
  }

  /// Frees the block.
  void release() {
    if (mapped_) munmap(data_, bytes_);
    else std::free(data_);
    data_ = nullptr;
    bytes_ = 0;
    mapped_ = false;
  }

  /// Bytes held.
  size_t capacityBytes() const { return bytes_; }

 private:
  void swap(ScratchBuffer& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(bytes_, o.bytes_);
    std::swap(mapped_, o.mapped_);
  }

  void grow(size_t bytes) {
    release();
    if (bytes < kHugePagesFrom) {
      const size_t rounded = (bytes + 63) / 64 * 64;
      data_ = static_cast<std::byte*>(std::aligned_alloc(64, rounded));
      if (data_ == nullptr) throw std::bad_alloc();
      bytes_ = rounded;
      return;
    }
    // Map 2 MiB more than needed, keep the 2 MiB-aligned part, unmap the rest.
    constexpr size_t kHuge = size_t(2) << 20;
    const size_t rounded = (bytes + kHuge - 1) / kHuge * kHuge;
    void* raw = mmap(nullptr, rounded + kHuge, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const auto start = reinterpret_cast<uintptr_t>(raw);
    const uintptr_t aligned = (start + kHuge - 1) / kHuge * kHuge;
    if (aligned > start) munmap(raw, aligned - start);
    if (const size_t tail = start + rounded + kHuge - (aligned + rounded)) munmap(reinterpret_cast<void*>(aligned + rounded), tail);
    data_ = reinterpret_cast<std::byte*>(aligned);
    bytes_ = rounded;
    mapped_ = true;
    madvise(data_, bytes_, MADV_HUGEPAGE);   // a hint; without huge pages it is still correct
  }

  std::byte* data_ = nullptr;
  size_t bytes_ = 0;
  bool mapped_ = false;
};

}  // namespace pa::bvh_detail
