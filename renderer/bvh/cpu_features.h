#pragma once
// What this CPU can run, for choosing the BVH layout and traversal kernel: the one place that
// asks the CPU (cpuid). Detected once per process, on first use.
#include <cpuid.h>

namespace pa::bvh_detail {

/// The CPU features the BVH kernels care about.
struct CpuFeatures {
  /// AVX-512 F/VL/BW/DQ with the OS saving the 512-bit state: what the AVX-512 kernels use.
  bool avx512 = false;
  /// avx512, and the CPU executes 512-bit operations at full width (the case where the 16-wide
  /// layout is the faster one): Intel CPUs and AMD Zen 5 or newer; Zen 4 splits them into two
  /// 256-bit halves.
  bool fullWidthAvx512 = false;
};

/// Whether this build has the AVX-512 kernels (x86-64-v3 builds; x86-64-v2 builds do not).
#if defined(__AVX2__)
inline constexpr bool kBuildHasAvx512Kernels = true;
#else
inline constexpr bool kBuildHasAvx512Kernels = false;
#endif

/// Reads the CPU's features (cpuid); cpuFeatures() caches the result.
inline CpuFeatures detectCpuFeatures() {
  __builtin_cpu_init();
  CpuFeatures f;
  f.avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
             __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq");
  unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
  if (!f.avx512 || !__get_cpuid(0, &eax, &ebx, &ecx, &edx)) return f;
  const bool amd = ebx == 0x68747541u && edx == 0x69746e65u && ecx == 0x444d4163u;   // "AuthenticAMD"
  if (!amd) {
    f.fullWidthAvx512 = true;
    return f;
  }
  if (!__get_cpuid(1, &eax, &ebx, &ecx, &edx)) return f;
  const unsigned family = ((eax >> 8) & 0xf) + (((eax >> 8) & 0xf) == 0xf ? ((eax >> 20) & 0xff) : 0);
  f.fullWidthAvx512 = family >= 0x1a;   // Zen 5 (family 1Ah); Zen 4 (19h) splits 512-bit operations
  return f;
}

/// This CPU's features, detected on the first call only.
inline const CpuFeatures& cpuFeatures() {
  static const CpuFeatures features = detectCpuFeatures();
  return features;
}

/// Whether the AVX-512 kernels (8- and 16-wide) can run: built in, and the CPU has AVX-512.
inline bool avx512KernelsAvailable() { return kBuildHasAvx512Kernels && cpuFeatures().avx512; }

}  // namespace pa::bvh_detail
