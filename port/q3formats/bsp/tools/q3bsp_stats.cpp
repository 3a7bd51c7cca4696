// q3bsp-stats: parses and tessellates maps, printing counts and timings.
//
//   q3bsp-stats [--error UNITS] [--no-stitch] [--seam-tolerance UNITS] [--seams] [--repeat N] [SPEC...]
//   SPEC: ARCHIVE.pk3 (every map in it), ARCHIVE.pk3:maps/NAME.bsp, or a loose FILE.bsp.
//   Without SPEC: every map of the installed OpenArena archives.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/bsp/entities.h"
#include "port/q3formats/bsp/tessellate.h"
#include "port/q3formats/bsp/tools/pk3_maps.h"
#include "port/q3formats/common/format_error.h"

namespace {

struct Settings {
  q3::TessellationOptions options;
  bool seams = false;
  int repeat = 3;
};

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Slowest map seen so far (parse + tessellate, best of the repeats).
struct Summary {
  size_t maps = 0;
  double slowestMs = 0;
  std::string slowest;
};

/// Prints one line per map; returns false if the map is malformed.
bool report(const std::string& label, const std::vector<std::byte>& bytes, const Settings& settings,
            Summary& summary) {
  double bestParse = 1e30, bestTess = 1e30;
  q3::BspFile bsp;
  std::vector<q3::SurfaceMesh> meshes;
  try {
    for (int run = 0; run < settings.repeat; ++run) {
      auto t0 = std::chrono::steady_clock::now();
      bsp = q3::parseBsp(bytes, label);
      bestParse = std::min(bestParse, msSince(t0));
      t0 = std::chrono::steady_clock::now();
      meshes = q3::tessellateSurfaces(bsp, settings.options);
      bestTess = std::min(bestTess, msSince(t0));
    }
  } catch (const q3::FormatError& e) {
    std::printf("%-60s ERROR %s\n", label.c_str(), e.what());
    return false;
  }
  size_t triangles[5] = {}, vertices = 0, patches = 0;
  for (const auto& m : meshes) {
    triangles[static_cast<int>(m.type)] += m.indices.size() / 3;
    vertices += m.vertices.size();
    patches += m.type == q3::SurfaceType::Patch;
  }
  std::vector<q3::Entity> entities;
  try {
    entities = q3::parseEntities(bsp.entities, label);
  } catch (const q3::FormatError& e) {
    bsp.warnings.push_back(e.what());  // geometry is still usable without entities
  }
  std::printf("%-44s %6.1f MB surf %5zu patches %4zu tris: faces %7zu soups %6zu patches %7zu verts %7zu "
              "models %3zu spawns %2zu lights %4zu | parse %6.1f ms tessellate %6.1f ms total %6.1f ms",
              label.c_str(), static_cast<double>(bytes.size()) / 1e6, bsp.surfaces.size(), patches,
              triangles[1], triangles[3], triangles[2], vertices, bsp.models.size(),
              q3::readSpawnCameras(entities).size(), q3::readLights(entities).size(), bestParse, bestTess,
              bestParse + bestTess);
  if (settings.seams) {
    const auto seams = q3::measurePatchSeams(meshes);
    std::printf(" | patch boundary edges %zu T-junctions %zu cracks %zu", seams.boundaryEdges, seams.tJunctions,
                seams.cracks);
  }
  std::printf("\n");
  ++summary.maps;
  if (bestParse + bestTess > summary.slowestMs) {
    summary.slowestMs = bestParse + bestTess;
    summary.slowest = label;
  }
  for (const auto& w : bsp.warnings) std::printf("    warning: %s\n", w.c_str());
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  std::vector<std::string> specs;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--error" && i + 1 < argc) settings.options.maxError = std::strtof(argv[++i], nullptr);
    else if (arg == "--repeat" && i + 1 < argc) settings.repeat = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--seam-tolerance" && i + 1 < argc) settings.options.seamTolerance = std::strtof(argv[++i], nullptr);
    else if (arg == "--no-stitch") settings.options.stitchPatches = false;
    else if (arg == "--seams") settings.seams = true;
    else if (arg == "--help" || arg == "-h") {
      std::printf("usage: %s [--error UNITS] [--no-stitch] [--seam-tolerance UNITS] [--seams] [--repeat N] [ARCHIVE.pk3[:maps/X.bsp] | FILE.bsp]...\n", argv[0]);
      return 0;
    } else specs.push_back(arg);
  }
  try {
    q3::tools::Pk3Reader pk3(argv[0]);
    if (specs.empty()) specs = q3::tools::openArenaMapArchives();
    bool ok = true;
    Summary summary;
    for (const auto& spec : specs) {
      const auto colon = spec.find(".pk3:");
      if (colon != std::string::npos) {
        pk3.mount(spec.substr(0, colon + 4));
        ok &= report(spec, pk3.read(spec.substr(colon + 5)), settings, summary);
      } else if (spec.ends_with(".pk3")) {
        pk3.mount(spec);
        for (const auto& map : pk3.listMaps()) ok &= report(spec + ":" + map, pk3.read(map), settings, summary);
      } else {
        std::ifstream in(spec, std::ios::binary);
        if (!in) throw std::runtime_error("cannot open " + spec);
        std::vector<char> raw((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::vector<std::byte> bytes(raw.size());
        std::transform(raw.begin(), raw.end(), bytes.begin(), [](char c) { return std::byte(c); });
        ok &= report(spec, bytes, settings, summary);
      }
    }
    std::printf("%zu maps; slowest parse + tessellate: %.1f ms (%s)\n", summary.maps, summary.slowestMs,
                summary.slowest.c_str());
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "q3bsp-stats: %s\n", e.what());
    return 2;
  }
}
