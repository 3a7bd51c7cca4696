// The AVX-512 (F/VL/BW/DQ) lanes of the wide traversal (wide_traversal_loop.h,
// wide_packet_loop.h), one set of lane traits for both layouts, chosen at run time
// (WideBvh::kernel, Blas's node width):
// - 8 lanes on the 8-wide BVH: hit children pushed with one register compress; when a
//   closest-hit ray enters three or more children, the others are pushed sorted by entry
//   distance (a 64-bit key sorting network), so the nearest is popped first; a leaf's accurate
//   plane distances for all eight lanes in one 8-wide double register.
// - 16 lanes on the 16-wide BVH (wide16_bvh.h): a closest-hit ray entering several children
//   takes them in the node's order for its octant (Wide16Node::order), one permutation instead
//   of a sort; leaves are one 8-wide pack (small leaves, read as sixteen lanes whose upper half
//   is never valid) or up to eight 16-wide packs.
// - Camera-ray packets of up to sixteen rays on either layout, one ray per lane.
// The float and double operations are those of the baseline lanes and the scalar reference, in
// the same order, so hit distances are bit-identical; on an exact tie in t the reported
// triangle may differ from the baseline kernel's (another visiting order).
//
// Only the functions here and the loops' templates carry the AVX-512 target attribute;
// everything they inline from the other headers keeps the build's ISA when emitted out of line,
// so no AVX-512 instruction can leak into code that runs on other CPUs. In x86-64-v2 builds the
// file holds only stubs of the 16-wide entry points (wide16Available() is false there).
#include <bit>
#include <cstdint>
#include <limits>
#include <type_traits>

#include <immintrin.h>

#include "renderer/bvh/cpu_features.h"
#include "renderer/bvh/simd.h"
#include "renderer/bvh/slab_test.h"
#include "renderer/bvh/watertight.h"
#include "renderer/bvh/wide16_bvh.h"
#include "renderer/bvh/wide_bvh.h"
#include "renderer/bvh/wide_traversal_stack.h"

namespace pa::bvh_detail {
bool wide16Available() { return avx512KernelsAvailable(); }
}  // namespace pa::bvh_detail

#if defined(__AVX2__)

#include "renderer/bvh/simd_avx512.h"

// GCC 12 reports the deliberately undefined pass-through operands of _mm512_cvtps_pd,
// _mm512_zextps256_ps512 and the masked reductions as (maybe) used uninitialized (false
// positives inside avx512fintrin.h; the loops' templates instantiate them, hence before them).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif

#define PA_BVH_KERNEL PA_AVX512
#include "renderer/bvh/wide_traversal_loop.h"
#include "renderer/bvh/wide_packet_loop.h"

namespace pa::bvh_detail {
namespace {

using simd::avx512::vfloat;

/// One layer of a sorting network on eight 64-bit keys: each lane meets the lane `partner`
/// names and keeps the larger key where takeMax has its bit, else the smaller.
PA_AVX512_INLINE __m512i compareExchange(__m512i keys, __m512i partner, __mmask8 takeMax) {
  const __m512i other = _mm512_permutexvar_epi64(partner, keys);
  return _mm512_mask_max_epi64(_mm512_min_epi64(keys, other), takeMax, keys, other);
}

/// AVX-512 lanes: kLanes = 8 on the 8-wide layout, 16 on the 16-wide one.
template <uint32_t kLanes>
struct Avx512Lanes {
  using Float = vfloat<int(kLanes)>;
  using Float8 = vfloat<8>;
  using Node = std::conditional_t<kLanes == 16, Wide16Node, WideNode>;
  using Bvh = std::conditional_t<kLanes == 16, Wide16Bvh, WideBvh>;
  using PlaneRay = simd::avx512::PlaneRay;
  static constexpr uint32_t kWidth = kLanes;
  static constexpr bool kOctantOrder = kLanes == 16;
  static constexpr bool kSmallLeaves = kLanes == 16;
  static constexpr bool kLaneByLaneHits = false;
  static constexpr int kEights = int(kLanes) / 8;   ///< Registers of eight doubles per Float.

  /// The node's child references, one per lane.
  PA_AVX512_INLINE static auto loadChildren(const Node& node) {
    if constexpr (kLanes == 16) return _mm512_load_si512(node.child);
    else return _mm256_load_si256(reinterpret_cast<const __m256i*>(node.child));
  }

  /// Pushes the children in mask (in lane order), with their entry distances when the stack
  /// keeps them, all lanes at once.
  template <bool kWithDistance>
  PA_AVX512_INLINE static void pushChildren(const Node& node, unsigned mask, Float tNear,
                                            TraversalStack<kWithDistance, kWidth>& stack) {
    simd::avx512::compressPush<kWithDistance>(stack, mask, loadChildren(node), tNear);
  }

  /// 8 lanes: pushes the children in mask (>= 2) farthest first, so the nearest is popped first:
  /// keys (entry distance as an ordered integer : child reference) sorted by a 19-comparator
  /// network.
  PA_AVX512_INLINE static void pushFarther(const WideNode& node, unsigned mask, Float tNear,
                                           TraversalStack<true>& stack) {
    // Floats compare like signed integers once the magnitude bits of negative ones are flipped
    // (an involution, undone below); distances are never NaN (tmin is a number).
    const __m256i bits = _mm256_castps_si256(tNear.v);
    const __m256i flip = _mm256_srli_epi32(_mm256_srai_epi32(bits, 31), 1);
    const __m256i order = _mm256_xor_si256(bits, flip);
    __m512i keys = _mm512_or_si512(_mm512_slli_epi64(_mm512_cvtepi32_epi64(order), 32),
                                   _mm512_cvtepu32_epi64(loadChildren(node)));
    keys = _mm512_mask_mov_epi64(_mm512_set1_epi64(std::numeric_limits<int64_t>::min()), static_cast<__mmask8>(mask), keys);
    keys = compareExchange(keys, _mm512_set_epi64(5, 4, 7, 6, 1, 0, 3, 2), 0x33);
    keys = compareExchange(keys, _mm512_set_epi64(3, 2, 1, 0, 7, 6, 5, 4), 0x0f);
    keys = compareExchange(keys, _mm512_set_epi64(6, 7, 4, 5, 2, 3, 0, 1), 0x55);
    keys = compareExchange(keys, _mm512_set_epi64(7, 6, 3, 2, 5, 4, 1, 0), 0x0c);
    keys = compareExchange(keys, _mm512_set_epi64(7, 3, 5, 1, 6, 2, 4, 0), 0x0a);
    keys = compareExchange(keys, _mm512_set_epi64(7, 5, 6, 3, 4, 1, 2, 0), 0x2a);
    const __m256i sortedOrder = _mm512_cvtepi64_epi32(_mm512_srli_epi64(keys, 32));
    const __m256i sortedFlip = _mm256_srli_epi32(_mm256_srai_epi32(sortedOrder, 31), 1);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(stack.node + stack.top), _mm512_cvtepi64_epi32(keys));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(stack.entry + stack.top), _mm256_xor_si256(sortedOrder, sortedFlip));
    stack.top += std::popcount(mask);
  }

  /// 8 lanes: index of the lane in mask (>= 2 bits) with the smallest entry distance (lowest
  /// lane on ties).
  PA_AVX512_INLINE static int nearestLane(unsigned mask, Float tNear) {
    const __mmask8 lanes = static_cast<__mmask8>(mask);
    const __m256 d = _mm256_mask_mov_ps(_mm256_set1_ps(std::numeric_limits<float>::infinity()), lanes, tNear.v);
    __m256 m = _mm256_min_ps(d, _mm256_shuffle_f32x4(d, d, 1));
    m = _mm256_min_ps(m, _mm256_permute_ps(m, 0x4e));
    m = _mm256_min_ps(m, _mm256_permute_ps(m, 0xb1));
    return std::countr_zero(static_cast<uint32_t>(_mm256_mask_cmp_ps_mask(lanes, d, m, _CMP_EQ_OQ)));
  }

  /// 16 lanes: the slots in mask as bits of their positions in the node's order for the octant
  /// (Wide16Node::order), farthest first from the lowest bit.
  PA_AVX512_INLINE static unsigned octantOrder(const Wide16Node& node, unsigned mask, int orderShift) {
    return _mm512_movepi32_mask(
        _mm512_permutexvar_epi32(positionSlots(node, orderShift), _mm512_movm_epi32(static_cast<__mmask16>(mask))));
  }
  /// 16 lanes: the slot at a position of the node's order for the octant.
  PA_AVX512_INLINE static int octantSlot(const Wide16Node& node, int position, int orderShift) {
    return (node.order[position] >> orderShift) & 15;
  }
  /// 16 lanes: the slot of each position of the node's order for the octant.
  PA_AVX512_INLINE static __m512i positionSlots(const Wide16Node& node, int orderShift) {
    return _mm512_and_si512(_mm512_srl_epi32(_mm512_load_si512(node.order), _mm_cvtsi32_si128(orderShift)),
                            _mm512_set1_epi32(15));
  }

  /// 16 lanes, closest hit: of the children in mask (>= 2), returns the nearest in the octant's
  /// order and pushes the others farthest first, so the nearer are popped first.
  PA_AVX512_INLINE static uint32_t enterInOctantOrder(const Wide16Node& node, unsigned mask, Float tNear,
                                                      int orderShift, TraversalStack<true, kWidth>& stack) {
    const __m512i order = positionSlots(node, orderShift);
    const uint32_t ordered = octantOrder(node, mask, orderShift);
    const int nearestPosition = 31 - std::countl_zero(ordered);
    const uint32_t next = node.child[octantSlot(node, nearestPosition, orderShift)];
    simd::avx512::compressPush<true>(stack, ordered & ~(1u << nearestPosition),
                                     _mm512_permutexvar_epi32(order, _mm512_load_si512(node.child)),
                                     Float(_mm512_permutexvar_ps(order, tNear.v)));
    return next;
  }

  /// All lanes of one vertex coordinate; a small (8-wide) pack read as 16 lanes has its upper
  /// lanes zero (never valid).
  template <class Pack>
  PA_AVX512_INLINE static Float loadVertex(const Pack& pack, int vertex, int axis) {
    if constexpr (kLanes == 16 && std::is_same_v<Pack, TrianglePack>)
      return _mm512_maskz_loadu_ps(0x00ff, pack.v[vertex][axis]);   // only the 8 lanes are read
    else
      return Float::load(pack.v[vertex][axis]);
  }

  /// The edge functions u, v, w of the lanes in onEdge, again in double (as the scalar test).
  PA_AVX512_INLINE static void redoEdgesInDouble(unsigned onEdge, Float ax, Float ay, Float bx, Float by, Float cx,
                                                 Float cy, Float& u, Float& v, Float& w) {
    using simd::avx512::differenceOfProductsInDouble;
    u = select(onEdge, u, differenceOfProductsInDouble(cx, by, cy, bx));
    v = select(onEdge, v, differenceOfProductsInDouble(ax, cy, ay, cx));
    w = select(onEdge, w, differenceOfProductsInDouble(bx, ay, by, ax));
  }

  /// planeHitDistance of the pack's lanes, eight at a time where some lane of hits is (fallback
  /// elsewhere, and where the ray runs parallel to the plane); a small pack's upper half never
  /// holds one.
  template <class Pack>
  PA_AVX512_INLINE static Float planeDistances(const Pack& pack, const PlaneRay& r, Float fallback, unsigned hits) {
    __m256 t[kEights];
    for (int part = 0; part < kEights; ++part) {
      t[part] = simd::avx512::eightLanes(fallback, part);
      if (hits >> (8 * part) & 0xff) t[part] = simd::avx512::planeDistances8(pack, 8 * part, r, t[part]);
    }
    return simd::avx512::joinEightLanes<int(kLanes)>(t);
  }

  /// 16 lanes, packets: rays[i] in lane i for the lanes given, the first of them in the other
  /// lanes (gathered from the rays' 32-byte records; only those rays are read).
  PA_AVX512_INLINE static PacketRays<Float> loadRays(const Ray* rays, unsigned lanes) {
    static_assert(kLanes == 16);
    const int first = std::countr_zero(lanes);
    // Each lane's record (the first live ray's in idle lanes), eight rays at a time transposed
    // into one field per register (loads and shuffles: 10% more primary rays per second than a
    // 512-bit gather per field on Zen 5, scripts/bench_maps.sh).
    const float* records[16];
    for (uint32_t lane = 0; lane < 16; ++lane) records[lane] = &rays[lanes >> lane & 1 ? lane : first].origin.x;
    __m256 low[kRayRecordFloats], high[kRayRecordFloats];
    simd::transposeEight(records, low);
    simd::transposeEight(records + 8, high);
    Float field[kRayRecordFloats];
    for (int k = 0; k < kRayRecordFloats; ++k) field[k] = _mm512_insertf32x8(_mm512_castps256_ps512(low[k]), high[k], 1);
    return packetRaysFromRecords(field);
  }

  /// Packets: each ray's origin and direction in double, eight rays per register.
  struct PacketPlane {
    __m512d o[3][kEights], d[3][kEights];
    PacketPlane() = default;
    PA_AVX512_INLINE PacketPlane(const Float (&origin)[3], const Float (&dir)[3]) {
      for (int axis = 0; axis < 3; ++axis)
        for (int part = 0; part < kEights; ++part) {
          o[axis][part] = _mm512_cvtps_pd(simd::avx512::eightLanes(origin[axis], part));
          d[axis][part] = _mm512_cvtps_pd(simd::avx512::eightLanes(dir[axis], part));
        }
    }
  };

  /// Packets: planeHitDistance of triangle `lane` of the pack for every ray (lane) of a part of
  /// eight with a ray in rays: the triangle's normal once, in double, then each ray's distance;
  /// fallback elsewhere and where the ray runs parallel to the plane.
  template <class Pack>
  PA_AVX512_INLINE static Float planeDistancesOverRays(const Pack& pack, int lane, const PacketPlane& r,
                                                       unsigned rays, Float fallback) {
    const double v0x = pack.v[0][0][lane], v0y = pack.v[0][1][lane], v0z = pack.v[0][2][lane];
    const double e1x = double(pack.v[1][0][lane]) - v0x, e1y = double(pack.v[1][1][lane]) - v0y,
                 e1z = double(pack.v[1][2][lane]) - v0z;
    const double e2x = double(pack.v[2][0][lane]) - v0x, e2y = double(pack.v[2][1][lane]) - v0y,
                 e2z = double(pack.v[2][2][lane]) - v0z;
    const __m512d nx = _mm512_set1_pd(e1y * e2z - e1z * e2y), ny = _mm512_set1_pd(e1z * e2x - e1x * e2z),
                  nz = _mm512_set1_pd(e1x * e2y - e1y * e2x);
    const __m512d px = _mm512_set1_pd(v0x), py = _mm512_set1_pd(v0y), pz = _mm512_set1_pd(v0z);
    __m256 t[kEights];
    for (int part = 0; part < kEights; ++part) {
      t[part] = simd::avx512::eightLanes(fallback, part);
      if (rays >> (8 * part) & 0xff)
        t[part] = simd::avx512::planeDistance8(nx, ny, nz, px, py, pz, r.o[0][part], r.o[1][part], r.o[2][part],
                                               r.d[0][part], r.d[1][part], r.d[2][part], t[part]);
    }
    return simd::avx512::joinEightLanes<int(kLanes)>(t);
  }
};

using Avx512Lanes8 = Avx512Lanes<kWideWidth>;
using Avx512Lanes16 = Avx512Lanes<kWide16Width>;

/// Camera-ray packets of sixteen rays over the 8-wide layout: Avx512Lanes16's operations, one
/// ray per lane, over the 8-wide nodes and packs (whose boxes are culled in Float8).
struct Avx512PacketLanesOverWide : Avx512Lanes16 {
  using Node = WideNode;
  using Bvh = WideBvh;
  static constexpr bool kOctantOrder = false;
  static constexpr bool kSmallLeaves = false;
};

}  // namespace

PA_AVX512 bool intersectWideAvx512(const WideBvh& bvh, Ray& ray, Hit& hit, const HitFilter& filter,
                                   uint32_t instanceId) {
  return traverse<Avx512Lanes8, false>(bvh, ray, ray.tmax, hit, filter, instanceId);
}

PA_AVX512 bool occludedWideAvx512(const WideBvh& bvh, const Ray& ray, const HitFilter& filter, uint32_t instanceId) {
  float tmax = ray.tmax;
  Hit unused;
  return traverse<Avx512Lanes8, true>(bvh, ray, tmax, unused, filter, instanceId);
}

PA_AVX512 unsigned intersectWidePacketAvx512(const WideBvh& bvh, Ray* rays, Hit* hits, unsigned active,
                                            const HitFilter* filters, uint32_t instanceId) {
  return intersectPacket<Avx512PacketLanesOverWide, intersectWideAvx512>(bvh, rays, hits, active, filters,
                                                                         instanceId);
}

PA_AVX512 unsigned occludedWidePacketAvx512(const WideBvh& bvh, const Ray* rays, unsigned active,
                                           const HitFilter* filters, uint32_t instanceId) {
  return occludedPacket<Avx512PacketLanesOverWide, occludedWideAvx512>(bvh, rays, active, filters, instanceId);
}

PA_AVX512 bool intersectWide16(const Wide16Bvh& bvh, Ray& ray, Hit& hit, const HitFilter& filter, uint32_t instanceId) {
  return traverse<Avx512Lanes16, false>(bvh, ray, ray.tmax, hit, filter, instanceId);
}

PA_AVX512 bool occludedWide16(const Wide16Bvh& bvh, const Ray& ray, const HitFilter& filter, uint32_t instanceId) {
  float tmax = ray.tmax;
  Hit unused;
  return traverse<Avx512Lanes16, true>(bvh, ray, tmax, unused, filter, instanceId);
}

PA_AVX512 unsigned intersectWide16Packet(const Wide16Bvh& bvh, Ray* rays, Hit* hits, unsigned active,
                                         const HitFilter* filters, uint32_t instanceId) {
  return intersectPacket<Avx512Lanes16, intersectWide16>(bvh, rays, hits, active, filters, instanceId);
}

PA_AVX512 unsigned occludedWide16Packet(const Wide16Bvh& bvh, const Ray* rays, unsigned active,
                                        const HitFilter* filters, uint32_t instanceId) {
  return occludedPacket<Avx512Lanes16, occludedWide16>(bvh, rays, active, filters, instanceId);
}

}  // namespace pa::bvh_detail

#else

namespace pa::bvh_detail {
bool intersectWide16(const Wide16Bvh&, Ray&, Hit&, const HitFilter&, uint32_t) { return false; }
bool occludedWide16(const Wide16Bvh&, const Ray&, const HitFilter&, uint32_t) { return false; }
unsigned intersectWide16Packet(const Wide16Bvh&, Ray*, Hit*, unsigned, const HitFilter*, uint32_t) { return 0; }
unsigned occludedWide16Packet(const Wide16Bvh&, const Ray*, unsigned, const HitFilter*, uint32_t) { return 0; }
}  // namespace pa::bvh_detail

#endif  // __AVX2__
