// Counts the module's heap allocations (operator new and malloc family called from its code), so
// that the steady state of play can be shown to allocate nothing (the `pt_allocations` command,
// the `allocations` field of r_pt_stats, port/engine_glue/tests/engine_allocations.sh).
#pragma once

#include <cstdint>

namespace glue {

/// Counts one allocation (called by the module's allocation hooks, allocation_hooks.cpp).
void noteAllocation();

/// Heap allocations made by the module's code since it was loaded (all threads).
uint64_t allocationCount();

/// Prints a backtrace (to stderr) of each of the next `count` allocations, then stops; 0 stops now.
void traceNextAllocations(uint32_t count);

}  // namespace glue
