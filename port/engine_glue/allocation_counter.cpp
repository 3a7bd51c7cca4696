// The count behind allocation_counter.h; allocation_hooks.cpp (linked into the module only)
// reports each allocation of the module's code here.
#include "port/engine_glue/allocation_counter.h"

#include <execinfo.h>
#include <unistd.h>

#include <atomic>

namespace glue {
namespace {

// Process-wide by nature: every thread of the module allocates through the hooks.
std::atomic<uint64_t> allocations{0};
std::atomic<uint32_t> tracesLeft{0};
thread_local bool tracing = false;   // backtrace() may allocate: never trace inside a trace

}  // namespace

void noteAllocation() {
  allocations.fetch_add(1, std::memory_order_relaxed);
  if (tracesLeft.load(std::memory_order_relaxed) == 0 || tracing) return;
  uint32_t left = tracesLeft.load(std::memory_order_relaxed);
  while (left > 0 && !tracesLeft.compare_exchange_weak(left, left - 1, std::memory_order_relaxed)) {
  }
  if (left == 0) return;
  tracing = true;
  void* frames[24];
  const int depth = backtrace(frames, 24);
  static constexpr char kHeader[] = "pathtracer: allocation at\n";
  [[maybe_unused]] const ssize_t written = write(STDERR_FILENO, kHeader, sizeof(kHeader) - 1);
  backtrace_symbols_fd(frames, depth, STDERR_FILENO);
  tracing = false;
}

uint64_t allocationCount() { return allocations.load(std::memory_order_relaxed); }

void traceNextAllocations(uint32_t count) { tracesLeft.store(count, std::memory_order_relaxed); }

}  // namespace glue
