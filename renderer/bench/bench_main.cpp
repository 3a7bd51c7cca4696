// bench: our BVH against Embree 3 on the same scene and the same rays.
//   bench (--scene FILE.gltf|glb | --synthetic soup:N|sphere:N|thin:N) [--threads N] [--reps R] [--build-reps B]
//         [--rays N] [--json] [--bins N] [--max-leaf N] [--traversal-cost X] [--split-budget X]
//         [--parallel-threshold N] [--width 8|16]
//         [--no-frames] [--frame-reps N] [--build-only] [--embree-robust] [--embree-tree]
//         [--embree-tree-splits X] [--isa avx2|native] [--instances N] [--primary-size WxH]
// --embree-robust builds Embree's scene with RTC_SCENE_FLAG_ROBUST (its conservative traversal
// and watertight-leaning kernels: the like-for-like comparison for our robust traversal).
// --embree-tree also traces our kernels over a tree built by Embree's rtcBuildBVH (same leaf
// rule as ours): the difference to our own tree is the tree's share of the gap to Embree.
// --embree-tree-splits X: that tree from Embree's high-quality build with spatial splits (SBVH,
// up to X x triangles more references): what spatial splits would give our kernels.
// --width picks our layout (BvhBuildConfig::nodeWidth; default: the faster one for this CPU).
// --isa avx2 runs our AVX2 kernel (what CPUs without AVX-512 run) against Embree's device limited
// to AVX2 ("isa=avx2"); native (the default) lets both pick their best kernels.
// Ray sets: incoherent (cosine bounces from visible points), shadow (visible points to random
// points near the top of the scene), primary (camera rays in 4x4 tiles: our packets against
// rtcIntersect16, and our rays one by one; --primary-size, default 1024x576: the game's lightmap
// preset traces 320x180 at a 640x360 window, whose packets span 3.2 times the angle), lamp
// shadow (from one lamp beside the camera to each visible point, in tile order: our any-hit
// packets against rtcOccluded16, and one by one).
// Per-ray figures are single-threaded rays per CPU second of the tracing thread (median over
// the repetitions, ours and Embree interleaved in each repetition); build times are wall-clock
// (and process CPU) medians over --build-reps interleaved repetitions (default 15: a build takes
// milliseconds), their ratio the median of each repetition's ratio, with N threads for both (one
// TBB arena; Embree's device also gets N threads).
// --instances N also traces the same rays through a game frame's two-level scene: the mesh as the
// static world plus N small movers (instanced_scene.h), our Tlas against Embree's instances.
// Frames: --frame-reps path-traced frames with 1 and 2 threads, alternating; medians of the wall
// clock and of the process CPU time, the median per-pair speedup and every wall-clock sample.
#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <tbb/task_arena.h>

#include "renderer/bench/bench_scene.h"
#include "renderer/bench/embree_tree.h"
#include "renderer/bench/frame_timing.h"
#include "renderer/bench/instanced_scene.h"
#include "renderer/bench/ray_sets.h"
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/wide_bvh.h"
#include "renderer/bvh/testing/embree_oracle.h"

namespace pa::bench {
namespace {

struct Options {
  std::string scene, synthetic;
  uint32_t threads = 1;
  uint32_t reps = 5;
  /// Repetitions of the builds: more than of the ray sets, since a build takes milliseconds and a
  /// slow spell over a few of five repetitions moved one side's median by up to 50% here.
  uint32_t buildReps = 15;
  uint32_t rays = 1u << 20;
  bool json = false;
  bool frames = true;
  uint32_t frameReps = 7;
  bool buildOnly = false;   ///< Time the builds only (for profiling the build).
  bool embreeRobust = false;   ///< Embree with RTC_SCENE_FLAG_ROBUST (its conservative traversal).
  bool embreeTree = false;     ///< Also trace our kernels over Embree's tree (embree_tree.h).
  EmbreeTreeConfig embreeTreeConfig;   ///< --embree-tree-splits X: Embree's SBVH, budget X.
  bool avx2 = false;           ///< --isa avx2: our AVX2 kernel against Embree limited to AVX2.
  uint32_t instances = 0;      ///< --instances N: movers of the two-level scene (0: not traced).
  uint32_t primaryWidth = 1024, primaryHeight = 576;   ///< --primary-size WxH: the camera's pixels.
  BvhBuildConfig build;
};

[[noreturn]] void usage(const std::string& error) {
  std::fprintf(stderr,
               "bench: %s\nusage: bench (--scene FILE | --synthetic soup:N|sphere:N|thin:N) [--threads N] "
               "[--reps R] [--build-reps B] [--rays N] [--json] [--bins N] [--max-leaf N] [--traversal-cost X] [--split-budget X] [--parallel-threshold N] [--width 8|16] [--no-frames] [--frame-reps N] [--build-only] [--embree-robust] [--embree-tree] [--embree-tree-splits X] [--isa avx2|native] [--instances N] [--primary-size WxH]\n",
               error.c_str());
  std::exit(2);
}

uint32_t parseCount(const char* text, const char* flag) {
  char* end = nullptr;
  const unsigned long v = std::strtoul(text, &end, 10);
  if (end == text || *end != '\0' || v == 0 || v > (1ul << 28)) usage(std::string("bad value for ") + flag);
  return static_cast<uint32_t>(v);
}

Options parseOptions(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= argc) usage("missing value after " + a);
      return argv[++i];
    };
    if (a == "--scene") o.scene = value();
    else if (a == "--synthetic") o.synthetic = value();
    else if (a == "--threads") o.threads = parseCount(value(), "--threads");
    else if (a == "--reps") o.reps = parseCount(value(), "--reps");
    else if (a == "--build-reps") o.buildReps = parseCount(value(), "--build-reps");
    else if (a == "--rays") o.rays = parseCount(value(), "--rays");
    else if (a == "--json") o.json = true;
    else if (a == "--no-frames") o.frames = false;
    else if (a == "--build-only") o.buildOnly = true;
    else if (a == "--embree-robust") o.embreeRobust = true;
    else if (a == "--embree-tree") o.embreeTree = true;
    else if (a == "--embree-tree-splits") {
      o.embreeTree = true;
      o.embreeTreeConfig.spatialSplits = true;
      char* end = nullptr;
      const char* text = value();
      o.embreeTreeConfig.splitBudget = std::strtof(text, &end);
      if (end == text || *end != '\0' || !(o.embreeTreeConfig.splitBudget > 0.0f && o.embreeTreeConfig.splitBudget <= 4.0f))
        usage("--embree-tree-splits takes a number in (0, 4]");
    }
    else if (a == "--isa") {
      const std::string isa = value();
      if (isa != "avx2" && isa != "native") usage("--isa takes avx2 or native");
      o.avx2 = isa == "avx2";
      o.build.allowAvx512 = !o.avx2;
    }
    else if (a == "--instances") o.instances = parseCount(value(), "--instances");
    else if (a == "--primary-size") {
      const std::string size = value();
      const size_t x = size.find('x');
      if (x == std::string::npos) usage("--primary-size takes WxH");
      o.primaryWidth = parseCount(size.substr(0, x).c_str(), "--primary-size");
      o.primaryHeight = parseCount(size.substr(x + 1).c_str(), "--primary-size");
      if (o.primaryWidth % 4 != 0 || o.primaryHeight % 4 != 0 || o.primaryWidth > 8192 || o.primaryHeight > 8192)
        usage("--primary-size takes multiples of 4 up to 8192");
    }
    else if (a == "--frame-reps") o.frameReps = parseCount(value(), "--frame-reps");
    else if (a == "--width") o.build.nodeWidth = parseCount(value(), "--width");
    else if (a == "--bins") o.build.binCount = parseCount(value(), "--bins");
    else if (a == "--max-leaf") o.build.maxLeafTriangles = parseCount(value(), "--max-leaf");
    else if (a == "--traversal-cost") o.build.traversalCost = std::strtof(value(), nullptr);
    else if (a == "--split-budget") o.build.splitBudget = std::strtof(value(), nullptr);
    else if (a == "--parallel-threshold") o.build.parallelThreshold = parseCount(value(), "--parallel-threshold");
    else usage("unknown argument " + a);
  }
  if (o.scene.empty() == o.synthetic.empty()) usage("give exactly one of --scene and --synthetic");
  return o;
}

double clockSeconds(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// Wall-clock seconds of f.
double wallSeconds(const std::function<void()>& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// CPU seconds f spends on the calling thread: the per-ray loops are single-threaded, and on a
/// shared machine this excludes time the thread waits for a core (see docs/performance.md).
double threadCpuSeconds(const std::function<void()>& f) {
  const double start = clockSeconds(CLOCK_THREAD_CPUTIME_ID);
  f();
  return clockSeconds(CLOCK_THREAD_CPUTIME_ID) - start;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Median of ours[i] / theirs[i] over interleaved repetitions: a slow spell of the machine slows
/// both builds of a repetition, and drops out of their ratio, where it would move one side's median.
double medianRatio(const std::vector<double>& ours, const std::vector<double>& theirs) {
  std::vector<double> ratios(std::min(ours.size(), theirs.size()));
  for (size_t i = 0; i < ratios.size(); ++i) ratios[i] = ours[i] / theirs[i];
  return median(std::move(ratios));
}

/// Medians and hit counts of one measured quantity, ours and Embree.
struct Pair {
  std::vector<double> ours, embree;
  uint64_t hitsOurs = 0, hitsEmbree = 0;
};

/// Checksum-carrying tracing loops (the hit counts are printed so the work cannot be elided
/// and both sides can be seen to agree).
/// Closest hits and occlusion through a Blas, a Tlas or an Embree scene (the same calls).
template <class Scene>
uint64_t traceClosest(const Scene& scene, const std::vector<Ray>& rays) {
  uint64_t hits = 0;
  for (Ray r : rays) {
    Hit h;
    hits += scene.intersect(r, h);
  }
  return hits;
}
template <class Scene>
uint64_t traceOccluded(const Scene& scene, const std::vector<Ray>& rays) {
  uint64_t hits = 0;
  for (const Ray& r : rays) hits += scene.occluded(r);
  return hits;
}
uint64_t traceClosest(const bvh_detail::WideBvh& bvh, const std::vector<Ray>& rays) {
  uint64_t hits = 0;
  for (Ray r : rays) {
    Hit h;
    hits += bvh_detail::isTraceableRay(r) && bvh_detail::intersectWide(bvh, r, h, {}, 0);
  }
  return hits;
}
uint64_t traceOccluded(const bvh_detail::WideBvh& bvh, const std::vector<Ray>& rays) {
  uint64_t hits = 0;
  for (const Ray& r : rays) hits += bvh_detail::isTraceableRay(r) && bvh_detail::occludedWide(bvh, r, {}, 0);
  return hits;
}
/// Our packet query over 16 consecutive rays at a time (the primary rays come in 4x4 tiles):
/// query(packet, hits, active, filters) is a Blas's or a Tlas's intersectPacket.
template <class Query>
uint64_t tracePacketsWith(const std::vector<Ray>& rays, Query&& query) {
  uint64_t hits = 0;
  std::array<Ray, kMaxPacketRays> packet;
  std::array<Hit, kMaxPacketRays> packetHits;
  const std::array<HitFilter, kMaxPacketRays> filters{};
  for (size_t i = 0; i < rays.size(); i += kMaxPacketRays) {
    const size_t n = std::min<size_t>(kMaxPacketRays, rays.size() - i);
    std::copy_n(rays.begin() + i, n, packet.begin());
    std::fill(packetHits.begin(), packetHits.end(), Hit{});
    hits += std::popcount(query(packet, packetHits, (1u << n) - 1, filters));
  }
  return hits;
}
uint64_t tracePackets(const Blas& blas, const std::vector<Ray>& rays) {
  return tracePacketsWith(rays, [&](auto& packet, auto& hits, uint32_t active, const auto& filters) {
    return blas.intersectPacket(packet, hits, active, filters);
  });
}
uint64_t tracePackets(const Tlas& tlas, const std::vector<Ray>& rays) {
  return tracePacketsWith(rays, [&](auto& packet, auto& hits, uint32_t active, const auto& filters) {
    return tlas.intersectPacket(packet, hits, active, 0xffffffffu, filters);
  });
}

/// Any hits of 16 consecutive rays at a time (the lamp's shadow rays come in tile order): ours
/// as Blas::occludedPacket, Embree's as rtcOccluded16.
uint64_t occludedPackets(const Blas& blas, const std::vector<Ray>& rays) {
  uint64_t hits = 0;
  const std::array<HitFilter, kMaxPacketRays> filters{};
  for (size_t i = 0; i < rays.size(); i += kMaxPacketRays) {
    const size_t n = std::min<size_t>(kMaxPacketRays, rays.size() - i);
    hits += std::popcount(blas.occludedPacket(std::span(rays).subspan(i, n), (1u << n) - 1, filters));
  }
  return hits;
}
uint64_t occludedPackets(const testing::EmbreeScene& scene, const std::vector<Ray>& rays) {
  uint64_t hits = 0;
  for (size_t i = 0; i < rays.size(); i += 16)
    hits += std::popcount(scene.occluded16(std::span(rays).subspan(i, std::min<size_t>(16, rays.size() - i))));
  return hits;
}

uint64_t tracePackets(const testing::EmbreeScene& scene, const std::vector<Ray>& rays) {
  uint64_t hits = 0;
  Ray packet[16];
  Hit packetHits[16];
  for (size_t i = 0; i < rays.size(); i += 16) {
    const size_t n = std::min<size_t>(16, rays.size() - i);
    std::copy_n(rays.begin() + i, n, packet);
    scene.intersect16({packet, n}, {packetHits, n});
    for (size_t k = 0; k < n; ++k) hits += packetHits[k].valid();
  }
  return hits;
}

/// Minor page faults of the process so far.
long minorPageFaults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

/// Wall-clock seconds, process CPU seconds and page faults of each repetition of a build.
struct BuildSamples {
  std::vector<double> wall, cpu;
  std::vector<long> pageFaults;
  void add(const std::function<void()>& build) {
    const long faults = minorPageFaults();
    const double cpuStart = clockSeconds(CLOCK_PROCESS_CPUTIME_ID);
    wall.push_back(wallSeconds(build));
    cpu.push_back(clockSeconds(CLOCK_PROCESS_CPUTIME_ID) - cpuStart);
    pageFaults.push_back(minorPageFaults() - faults);
  }
};

/// Counts as a JSON list.
std::string countList(const std::vector<long>& counts) {
  std::string out = "[";
  for (size_t i = 0; i < counts.size(); ++i) out += (i ? ", " : "") + std::to_string(counts[i]);
  return out + "]";
}

/// Seconds as a JSON list of milliseconds.
std::string msList(const std::vector<double>& seconds) {
  std::string out = "[";
  for (size_t i = 0; i < seconds.size(); ++i) out += (i ? ", " : "") + std::to_string(seconds[i] * 1e3);
  return out + "]";
}

double mrays(size_t rays, double seconds) { return double(rays) / seconds * 1e-6; }

}  // namespace

int run(int argc, char** argv) {
  const Options opt = parseOptions(argc, argv);
  BenchScene scene = opt.scene.empty() ? makeSyntheticScene(opt.synthetic) : loadGltfScene(opt.scene);
  const testing::TestMesh& mesh = scene.mesh;
  // Frames first: an Embree device made with "threads=N" limits TBB's parallelism for the whole
  // process while it lives, which would cap the renderer's 2-thread arena at N.
  FrameTimes frames = opt.frames ? measureFrames(scene, opt.frameReps) : FrameTimes{};
  if (!opt.frames) frames.note = "skipped (--no-frames)";
  tbb::task_arena arena(static_cast<int>(opt.threads));
  testing::EmbreeDevice device("threads=" + std::to_string(opt.threads) + (opt.avx2 ? ",isa=avx2" : ""));

  // Build times (median over repetitions, interleaved). Each side replaces its previous build
  // inside its timed region: our Blas rebuilds in place (as the renderer's meshes do), Embree's
  // previous scene is released and a new one made.
  BuildSamples ours, theirs;
  Blas blas;
  std::unique_ptr<testing::EmbreeScene> embree;
  for (uint32_t rep = 0; rep < opt.buildReps; ++rep) {
    ours.add([&] { arena.execute([&] { blas.build(mesh.input(), opt.build); }); });
    theirs.add([&] {
      embree.reset();
      testing::EmbreeSceneOptions embreeOptions;
      embreeOptions.robust = opt.embreeRobust;
      auto s = std::make_unique<testing::EmbreeScene>(device, embreeOptions);
      s->addMesh(mesh);
      arena.execute([&] { s->commit(); });
      embree = std::move(s);
    });
  }
  const std::vector<double>& buildOurs = ours.wall;
  const std::vector<double>& buildEmbree = theirs.wall;
  const std::vector<double>& buildCpuOurs = ours.cpu;
  const std::vector<double>& buildCpuEmbree = theirs.cpu;

  if (opt.buildOnly) {
    std::printf("build ms ours %.3f embree %.3f (wall), CPU %.3f / %.3f, median of %u\n", median(buildOurs) * 1e3,
                median(buildEmbree) * 1e3, median(buildCpuOurs) * 1e3, median(buildCpuEmbree) * 1e3, opt.buildReps);
    std::printf("build CPU ms per repetition: ours %s, embree %s\n", msList(buildCpuOurs).c_str(),
                msList(buildCpuEmbree).c_str());
    std::printf("build wall ms per repetition: ours %s, embree %s\n", msList(ours.wall).c_str(), msList(theirs.wall).c_str());
    std::printf("page faults per repetition: ours %s, embree %s\n", countList(ours.pageFaults).c_str(),
                countList(theirs.pageFaults).c_str());
    return 0;
  }
  const RaySets rays = makeRaySets(scene, blas, opt.primaryWidth, opt.primaryHeight, opt.rays, 7);
  Pair incoherent, shadow, primary, primarySingle;   // primary: our packets; primarySingle: ray by ray
  Pair lampShadow, lampShadowSingle;                 // the same for shadow rays toward one lamp
  // Our kernels over Embree's tree (--embree-tree): .ours holds those samples, .embree is unused.
  Pair incoherentEmbreeTree, shadowEmbreeTree;
  bvh_detail::WideBvh embreeTree;
  if (opt.embreeTree) embreeTree = buildWideFromEmbreeTree(device.get(), bvh_detail::makeTriangleMesh(mesh.input()), opt.embreeTreeConfig);
  for (uint32_t rep = 0; rep < opt.reps; ++rep) {
    incoherent.ours.push_back(threadCpuSeconds([&] { incoherent.hitsOurs = traceClosest(blas, rays.incoherent); }));
    incoherent.embree.push_back(threadCpuSeconds([&] { incoherent.hitsEmbree = traceClosest(*embree, rays.incoherent); }));
    shadow.ours.push_back(threadCpuSeconds([&] { shadow.hitsOurs = traceOccluded(blas, rays.shadow); }));
    shadow.embree.push_back(threadCpuSeconds([&] { shadow.hitsEmbree = traceOccluded(*embree, rays.shadow); }));
    if (opt.embreeTree) {
      incoherentEmbreeTree.ours.push_back(
          threadCpuSeconds([&] { incoherentEmbreeTree.hitsOurs = traceClosest(embreeTree, rays.incoherent); }));
      shadowEmbreeTree.ours.push_back(
          threadCpuSeconds([&] { shadowEmbreeTree.hitsOurs = traceOccluded(embreeTree, rays.shadow); }));
    }
    primary.ours.push_back(threadCpuSeconds([&] { primary.hitsOurs = tracePackets(blas, rays.primary); }));
    primarySingle.ours.push_back(threadCpuSeconds([&] { primarySingle.hitsOurs = traceClosest(blas, rays.primary); }));
    primary.embree.push_back(threadCpuSeconds([&] { primary.hitsEmbree = tracePackets(*embree, rays.primary); }));
    lampShadow.ours.push_back(threadCpuSeconds([&] { lampShadow.hitsOurs = occludedPackets(blas, rays.lampShadow); }));
    lampShadowSingle.ours.push_back(
        threadCpuSeconds([&] { lampShadowSingle.hitsOurs = traceOccluded(blas, rays.lampShadow); }));
    lampShadow.embree.push_back(
        threadCpuSeconds([&] { lampShadow.hitsEmbree = occludedPackets(*embree, rays.lampShadow); }));
  }
  // The two-level scene (--instances): the same rays, interleaved the same way.
  Pair twoIncoherent, twoShadow, twoPrimary;
  InstancedScene twoLevel;
  if (opt.instances > 0) {
    buildInstancedScene(scene, blas, *embree, device, opt.instances, 11, twoLevel);
    const testing::EmbreeScene& top = *twoLevel.embreeTop;
    for (uint32_t rep = 0; rep < opt.reps; ++rep) {
      twoIncoherent.ours.push_back(threadCpuSeconds([&] { twoIncoherent.hitsOurs = traceClosest(twoLevel.tlas, rays.incoherent); }));
      twoIncoherent.embree.push_back(threadCpuSeconds([&] { twoIncoherent.hitsEmbree = traceClosest(top, rays.incoherent); }));
      twoShadow.ours.push_back(threadCpuSeconds([&] { twoShadow.hitsOurs = traceOccluded(twoLevel.tlas, rays.shadow); }));
      twoShadow.embree.push_back(threadCpuSeconds([&] { twoShadow.hitsEmbree = traceOccluded(top, rays.shadow); }));
      twoPrimary.ours.push_back(threadCpuSeconds([&] { twoPrimary.hitsOurs = tracePackets(twoLevel.tlas, rays.primary); }));
      twoPrimary.embree.push_back(threadCpuSeconds([&] { twoPrimary.hitsEmbree = tracePackets(top, rays.primary); }));
    }
  }
  // Mrays/s of ours and Embree and their ratio, from a pair's medians.
  struct Rate {
    double ours = 0.0, embree = 0.0;
    double ratio() const { return embree > 0.0 ? ours / embree : 0.0; }
  };
  const auto rate = [](const Pair& p, size_t count) {
    return p.ours.empty() ? Rate{} : Rate{mrays(count, median(p.ours)), mrays(count, median(p.embree))};
  };
  const Rate twoI = rate(twoIncoherent, rays.incoherent.size()), twoS = rate(twoShadow, rays.shadow.size());
  const Rate twoP = rate(twoPrimary, rays.primary.size());
  std::string twoLevelJson;
  if (opt.instances > 0) {
    char buffer[768];
    std::snprintf(buffer, sizeof buffer,
                  "\"instances\": %u, \"mrays_incoherent_two_level_ours\": %.3f, \"mrays_incoherent_two_level_embree\": %.3f, "
                  "\"incoherent_two_level_ratio\": %.3f, \"mrays_shadow_two_level_ours\": %.3f, "
                  "\"mrays_shadow_two_level_embree\": %.3f, \"shadow_two_level_ratio\": %.3f, "
                  "\"mrays_primary_two_level_ours\": %.3f, \"mrays_primary_two_level_embree\": %.3f, "
                  "\"primary_two_level_ratio\": %.3f, \"hits_two_level_ours\": [%llu, %llu, %llu], "
                  "\"hits_two_level_embree\": [%llu, %llu, %llu], ",
                  opt.instances, twoI.ours, twoI.embree, twoI.ratio(), twoS.ours, twoS.embree, twoS.ratio(), twoP.ours,
                  twoP.embree, twoP.ratio(), (unsigned long long)twoIncoherent.hitsOurs,
                  (unsigned long long)twoShadow.hitsOurs, (unsigned long long)twoPrimary.hitsOurs,
                  (unsigned long long)twoIncoherent.hitsEmbree, (unsigned long long)twoShadow.hitsEmbree,
                  (unsigned long long)twoPrimary.hitsEmbree);
    twoLevelJson = buffer;
  }

  const double bOurs = median(buildOurs) * 1e3, bEmbree = median(buildEmbree) * 1e3;
  const double bCpuOurs = median(buildCpuOurs) * 1e3, bCpuEmbree = median(buildCpuEmbree) * 1e3;
  const double bRatio = medianRatio(buildOurs, buildEmbree), bCpuRatio = medianRatio(buildCpuOurs, buildCpuEmbree);
  const double iOurs = mrays(rays.incoherent.size(), median(incoherent.ours));
  const double iEmbree = mrays(rays.incoherent.size(), median(incoherent.embree));
  const double sOurs = mrays(rays.shadow.size(), median(shadow.ours));
  const double sEmbree = mrays(rays.shadow.size(), median(shadow.embree));
  const double pOurs = mrays(rays.primary.size(), median(primary.ours));
  const double pEmbree = mrays(rays.primary.size(), median(primary.embree));
  const double pSingle = mrays(rays.primary.size(), median(primarySingle.ours));
  const double lOurs = mrays(rays.lampShadow.size(), median(lampShadow.ours));
  const double lEmbree = mrays(rays.lampShadow.size(), median(lampShadow.embree));
  const double lSingle = mrays(rays.lampShadow.size(), median(lampShadowSingle.ours));
  const double iTree = opt.embreeTree ? mrays(rays.incoherent.size(), median(incoherentEmbreeTree.ours)) : 0.0;
  const double sTree = opt.embreeTree ? mrays(rays.shadow.size(), median(shadowEmbreeTree.ours)) : 0.0;
  std::string embreeTreeJson;
  if (opt.embreeTree) {
    char buffer[512];
    std::snprintf(buffer, sizeof buffer,
                  "\"embree_tree_nodes\": %zu, \"embree_tree_packs\": %zu, \"mrays_incoherent_ours_embree_tree\": %.3f, "
                  "\"incoherent_ratio_embree_tree\": %.3f, \"mrays_shadow_ours_embree_tree\": %.3f, "
                  "\"shadow_ratio_embree_tree\": %.3f, \"hits_incoherent_ours_embree_tree\": %llu, "
                  "\"hits_shadow_ours_embree_tree\": %llu, ",
                  embreeTree.nodes.size(), embreeTree.packs.size(), iTree, iTree / iEmbree, sTree, sTree / sEmbree,
                  (unsigned long long)incoherentEmbreeTree.hitsOurs, (unsigned long long)shadowEmbreeTree.hitsOurs);
    embreeTreeJson = buffer;
  }
  const bool avx512 = opt.build.allowAvx512 && bvh_detail::wideKernelAvailable(bvh_detail::WideKernel::Avx512);
  const char* ourKernel = blas.nodeWidth() == 16 ? "avx512-16wide" : avx512 ? "avx512" : "baseline";
  auto frame = [](const std::optional<double>& v) { return v ? std::to_string(*v) : std::string("null"); };
  auto samples = [](const std::vector<double>& v) {
    std::string out = "[";
    for (size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + std::to_string(v[i]);
    return out + "]";
  };

  if (opt.json) {
    std::printf(
        "{\"scene\": \"%s\", \"triangles\": %u, \"threads\": %u, \"reps\": %u, \"build_reps\": %u, \"embree_isa\": \"%s\", \"our_kernel\": \"%s\", \"embree_robust\": %s, "
        "\"build_ms_ours\": %.3f, \"build_ms_embree\": %.3f, \"build_ratio\": %.3f, "
        "\"build_cpu_ms_ours\": %.3f, \"build_cpu_ms_embree\": %.3f, \"build_cpu_ratio\": %.3f, "
        "\"rays_incoherent\": %zu, \"mrays_incoherent_ours\": %.3f, \"mrays_incoherent_embree\": %.3f, "
        "\"incoherent_ratio\": %.3f, \"rays_shadow\": %zu, \"mrays_shadow_ours\": %.3f, "
        "\"mrays_shadow_embree\": %.3f, \"shadow_ratio\": %.3f, \"rays_primary\": %zu, "
        "\"mrays_primary_ours\": %.3f, \"mrays_primary_embree\": %.3f, \"primary_ratio\": %.3f, "
        "\"mrays_primary_single_ours\": %.3f, \"primary_single_ratio\": %.3f, \"rays_lamp_shadow\": %zu, "
        "\"mrays_lamp_shadow_ours\": %.3f, \"mrays_lamp_shadow_embree\": %.3f, \"lamp_shadow_ratio\": %.3f, "
        "\"mrays_lamp_shadow_single_ours\": %.3f, \"lamp_shadow_single_ratio\": %.3f, "
        "\"hits_lamp_shadow_ours\": %llu, \"hits_lamp_shadow_embree\": %llu, "
        "\"hits_incoherent_ours\": %llu, \"hits_incoherent_embree\": %llu, \"hits_shadow_ours\": %llu, "
        "\"hits_shadow_embree\": %llu, \"hits_primary_ours\": %llu, \"hits_primary_embree\": %llu, %s%s"
        "\"frame_ms_1t\": %s, \"frame_ms_2t\": %s, \"frame_cpu_ms_1t\": %s, \"frame_cpu_ms_2t\": %s, "
        "\"frame_speedup_2t\": %s, \"frame_samples_ms_1t\": %s, \"frame_samples_ms_2t\": %s, \"frame_note\": \"%s\"}\n",
        scene.name.c_str(), mesh.triangleCount(), opt.threads, opt.reps, opt.buildReps, device.isaDescription().c_str(), ourKernel, opt.embreeRobust ? "true" : "false", bOurs,
        bEmbree, bRatio, bCpuOurs, bCpuEmbree, bCpuRatio, rays.incoherent.size(), iOurs, iEmbree, iOurs / iEmbree, rays.shadow.size(),
        sOurs, sEmbree, sOurs / sEmbree, rays.primary.size(), pOurs, pEmbree, pOurs / pEmbree,
        pSingle, pSingle / pEmbree, rays.lampShadow.size(), lOurs, lEmbree, lOurs / lEmbree, lSingle, lSingle / lEmbree,
        (unsigned long long)lampShadow.hitsOurs, (unsigned long long)lampShadow.hitsEmbree,
        (unsigned long long)incoherent.hitsOurs, (unsigned long long)incoherent.hitsEmbree,
        (unsigned long long)shadow.hitsOurs, (unsigned long long)shadow.hitsEmbree,
        (unsigned long long)primary.hitsOurs, (unsigned long long)primary.hitsEmbree, embreeTreeJson.c_str(),
        twoLevelJson.c_str(),
        frame(frames.oneThreadMs).c_str(), frame(frames.twoThreadsMs).c_str(), frame(frames.oneThreadCpuMs).c_str(),
        frame(frames.twoThreadsCpuMs).c_str(), frame(frames.speedup).c_str(), samples(frames.oneThreadSamplesMs).c_str(),
        samples(frames.twoThreadsSamplesMs).c_str(), frames.note.c_str());
    return 0;
  }
  std::printf("scene %s: %u triangles, build threads %u, %u repetitions (%u of the builds; medians), Embree ISA %s%s, our kernel %s\n",
              scene.name.c_str(), mesh.triangleCount(), opt.threads, opt.reps, opt.buildReps, device.isaDescription().c_str(),
              opt.embreeRobust ? ", RTC_SCENE_FLAG_ROBUST" : "", ourKernel);
  std::printf("%-28s %12s %12s %8s\n", "", "ours", "embree", "ratio");
  std::printf("%-28s %12.2f %12.2f %8.3f\n", "build ms (wall)", bOurs, bEmbree, bRatio);
  std::printf("%-28s %12.2f %12.2f %8.3f\n", "build ms (process CPU)", bCpuOurs, bCpuEmbree, bCpuRatio);
  std::printf("%-28s %12.3f %12.3f %8.3f\n", "incoherent Mrays/s (1t)", iOurs, iEmbree, iOurs / iEmbree);
  std::printf("%-28s %12.3f %12.3f %8.3f\n", "shadow Mrays/s (1t)", sOurs, sEmbree, sOurs / sEmbree);
  std::printf("%-28s %12.3f %12.3f %8.3f\n", "primary Mrays/s (1t)", pOurs, pEmbree, pOurs / pEmbree);
  std::printf("%-28s %12.3f %12.3f %8.3f\n", "primary, ray by ray", pSingle, pEmbree, pSingle / pEmbree);
  std::printf("%-28s %12.3f %12.3f %8.3f\n", "lamp shadow Mrays/s (1t)", lOurs, lEmbree, lOurs / lEmbree);
  std::printf("%-28s %12.3f %12.3f %8.3f\n", "lamp shadow, ray by ray", lSingle, lEmbree, lSingle / lEmbree);
  if (opt.embreeTree) {
    std::printf("%-28s %12.3f %12.3f %8.3f\n", "incoherent, Embree's tree", iTree, iEmbree, iTree / iEmbree);
    std::printf("%-28s %12.3f %12.3f %8.3f\n", "shadow, Embree's tree", sTree, sEmbree, sTree / sEmbree);
    std::printf("Embree's tree in our layout: %zu nodes, %zu packs; hits incoherent %llu shadow %llu\n",
                embreeTree.nodes.size(), embreeTree.packs.size(), (unsigned long long)incoherentEmbreeTree.hitsOurs,
                (unsigned long long)shadowEmbreeTree.hitsOurs);
  }
  if (opt.instances > 0) {
    std::printf("two-level scene: the world and %u movers (instances of a %u-triangle sphere)\n", opt.instances,
                twoLevel.mover.triangleCount());
    std::printf("%-28s %12.3f %12.3f %8.3f\n", "  incoherent Mrays/s (1t)", twoI.ours, twoI.embree, twoI.ratio());
    std::printf("%-28s %12.3f %12.3f %8.3f\n", "  shadow Mrays/s (1t)", twoS.ours, twoS.embree, twoS.ratio());
    std::printf("%-28s %12.3f %12.3f %8.3f\n", "  primary Mrays/s (1t)", twoP.ours, twoP.embree, twoP.ratio());
    std::printf("  hits ours/embree: incoherent %llu/%llu shadow %llu/%llu primary %llu/%llu\n",
                (unsigned long long)twoIncoherent.hitsOurs, (unsigned long long)twoIncoherent.hitsEmbree,
                (unsigned long long)twoShadow.hitsOurs, (unsigned long long)twoShadow.hitsEmbree,
                (unsigned long long)twoPrimary.hitsOurs, (unsigned long long)twoPrimary.hitsEmbree);
  }
  std::printf("hits ours/embree: incoherent %llu/%llu shadow %llu/%llu primary %llu/%llu lamp shadow %llu/%llu\n",
              (unsigned long long)incoherent.hitsOurs, (unsigned long long)incoherent.hitsEmbree,
              (unsigned long long)shadow.hitsOurs, (unsigned long long)shadow.hitsEmbree,
              (unsigned long long)primary.hitsOurs, (unsigned long long)primary.hitsEmbree,
              (unsigned long long)lampShadow.hitsOurs, (unsigned long long)lampShadow.hitsEmbree);
  std::printf("frame ms 640x360 1spp: 1 thread %s (CPU %s), 2 threads %s (CPU %s), speedup %s (%s)\n",
              frame(frames.oneThreadMs).c_str(), frame(frames.oneThreadCpuMs).c_str(), frame(frames.twoThreadsMs).c_str(),
              frame(frames.twoThreadsCpuMs).c_str(), frame(frames.speedup).c_str(), frames.note.c_str());
  std::printf("frame samples ms: 1 thread %s, 2 threads %s\n", samples(frames.oneThreadSamplesMs).c_str(),
              samples(frames.twoThreadsSamplesMs).c_str());
  return 0;
}

}  // namespace pa::bench

int main(int argc, char** argv) {
  try {
    return pa::bench::run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench: %s\n", e.what());
    return 1;
  }
}
