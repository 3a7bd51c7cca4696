// pa-all-maps: renders every map of a game folder from a player spawn point with pa-render
// (lightmap, direct and path integrators), checks that each picture is plausible, and writes a
// results table and a contact sheet. See README.md.
#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <optional>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <mutex>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <stb_image_write.h>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/vfs/game_filesystem.h"
#include "tests/all_maps_render/arena_info.h"
#include "tests/all_maps_render/contact_sheet.h"
#include "tests/all_maps_render/map_checks.h"
#include "tests/all_maps_render/render_run.h"

namespace {

namespace fs = std::filesystem;
using namespace pa::allmaps;

constexpr int kExitPass = 0;
constexpr int kExitFail = 1;
constexpr int kExitUsage = 2;
constexpr int kExitSkip = 77;   // CTest SKIP_RETURN_CODE: the game data is not installed

constexpr const char* kUsage = R"(Usage: pa-all-maps --pa-render PATH --out DIR [options]

Renders every map of the game folder with pa-render from the first player spawn point that
stands on a floor, preferring the spawn class of the map's first game type in the game's arena
lists (scripts/arenas.txt, scripts/*.arena: CTF-like games start at team_CTF_*player), in the
lightmap, direct and path integrators (--tonemap clamp; lightmap exposed automatically, direct
and path at the lightmap's gain), and checks that each picture is plausible (not black, not all
sky, spawn inside the level). Writes DIR/results.md, DIR/results.tsv, DIR/contact_sheet.png and
the renders (DIR/renders/MAP_INTEGRATOR.{png,exr,json}, DIR/renders/MAP.log: one pa-render
process renders a map's three pictures over the map loaded once).

  --pa-render PATH        The pa-render executable (required)
  --out DIR               Output folder (required; created)
  --game-dir DIR          Game folder (default /usr/share/games/openarena/baseoa)
  --maps A,B,...          Only these maps (names without maps/ and .bsp); default: all
  --known-problems FILE   "MAP lightmap|direct|path|* REASON" lines expected to fail (README.md)
  --width W --height H    Render size (default 160 x 90)
  --lightmap-spp N        Samples per pixel of the lightmap renders (default 2)
  --direct-spp N          Samples per pixel of the direct renders (default 8)
  --path-spp N            Samples per pixel of the path renders (default 16, pa-render's
                          default; bounces: pa-render's default, 4)
  --threads T             pa-render --threads (default 0 = all cores)
  --jobs J                Maps checked at once, each by its own pa-render process (default 2:
                          a call spends most of its time loading the map on one core); the
                          pictures and reports do not depend on it
  --columns C             Contact sheet cells per row (default 6)
  --exposure GAIN         Judge every render at this fixed gain (1 = the stock look) instead
                          of the default: lightmap --exposure auto, direct and path at the
                          lightmap's gain
  --reuse                 Re-check the renders an earlier run left in DIR/renders instead of
                          rendering again, where its --stats JSON shows the same settings;
                          the others are rendered

Exit status: 0 every check passed (known problems aside), 1 a check failed, 2 usage error,
77 the game folder or its maps are missing (a skip for CTest).
)";

struct Options {
  fs::path paRender;
  fs::path out;
  fs::path gameDir = "/usr/share/games/openarena/baseoa";
  std::vector<std::string> maps;
  fs::path knownProblems;
  uint32_t width = 160, height = 90;
  uint32_t lightmapSpp = 2, directSpp = 8, pathSpp = 16;
  uint32_t threads = 0;
  uint32_t jobs = 2;
  uint32_t columns = 6;
  bool reuse = false;
  std::optional<std::string> fixedExposure;   ///< --exposure: one gain for every render instead of auto.
};

bool parseCount(std::string_view text, uint32_t lo, uint32_t hi, uint32_t& out) {
  uint32_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < lo || value > hi) return false;
  out = value;
  return true;
}

std::vector<std::string> splitList(std::string_view text) {
  std::vector<std::string> items;
  std::string item;
  std::istringstream in{std::string(text)};
  while (std::getline(in, item, ','))
    if (!item.empty()) items.push_back(item);
  return items;
}

/// Returns an error message, or "" when the options are complete.
std::string parseOptions(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view name = argv[i];
    if (name == "-h" || name == "--help") return "help";
    if (name == "--reuse") {
      o.reuse = true;
      continue;
    }
    if (i + 1 >= argc) return std::string(name) + ": missing value";
    const std::string_view value = argv[++i];
    bool ok = true;
    if (name == "--pa-render") o.paRender = value;
    else if (name == "--out") o.out = value;
    else if (name == "--game-dir") o.gameDir = value;
    else if (name == "--maps") o.maps = splitList(value);
    else if (name == "--known-problems") o.knownProblems = value;
    else if (name == "--width") ok = parseCount(value, 8, 4096, o.width);
    else if (name == "--height") ok = parseCount(value, 8, 4096, o.height);
    else if (name == "--lightmap-spp") ok = parseCount(value, 1, 4096, o.lightmapSpp);
    else if (name == "--direct-spp") ok = parseCount(value, 1, 4096, o.directSpp);
    else if (name == "--path-spp") ok = parseCount(value, 1, 4096, o.pathSpp);
    else if (name == "--threads") ok = parseCount(value, 0, 4096, o.threads);
    else if (name == "--jobs") ok = parseCount(value, 1, 64, o.jobs);
    else if (name == "--columns") ok = parseCount(value, 1, 64, o.columns);
    else if (name == "--exposure") {
      char* end = nullptr;
      const double gain = std::strtod(std::string(value).c_str(), &end);
      ok = end && *end == '\0' && gain > 0.0 && std::isfinite(gain);
      if (ok) o.fixedExposure = std::string(value);
    }
    else return "unknown option " + std::string(name);
    if (!ok) return std::string(name) + ": bad value \"" + std::string(value) + "\"";
  }
  if (o.paRender.empty()) return "missing --pa-render";
  if (o.out.empty()) return "missing --out";
  return "";
}

std::string readTextFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// "maps/oa_dm1.bsp" -> "oa_dm1".
std::string mapName(const std::string& gamePath) { return fs::path(gamePath).stem().string(); }

/// An integrator and its samples per pixel.
struct IntegratorRun {
  const char* name;
  uint32_t spp;
};

/// Surveys, renders and checks one map.
MapResult checkMap(const Options& o, const q3::GameFileSystem& game, const ArenaIndex& arenas,
                   const std::string& gamePath, const std::vector<KnownProblem>& known, std::vector<RgbaImage>& images) {
  MapResult result;
  result.map = mapName(gamePath);
  if (const ArenaEntry* entry = arenas.find(result.map)) result.arena = *entry;
  result.archive = fs::path(game.sourceOf(gamePath)).filename().string();
  result.mapExpectedBecause = knownProblemReason(known, result.map, "*").value_or("");
  const PlausibilityThresholds thresholds;
  // All are judged in the stock renderer's look (clamp: no curve), so that one set of
  // thresholds serves all; the filmic default (aces) would darken dim maps' shadows further.
  // Path: pa-render's default integrator (the offline render a user gets), at its defaults.
  const std::vector<IntegratorRun> runs = {
      {"lightmap", o.lightmapSpp}, {"direct", o.directSpp}, {"path", o.pathSpp}};
  images.assign(runs.size(), RgbaImage{});
  try {
    const auto bytes = game.readFile(gamePath);
    if (!bytes) throw std::runtime_error(gamePath + ": listed but not readable");
    const q3::BspFile bsp = q3::parseBsp(*bytes, gamePath);
    result.survey = surveyMap(bsp, result.arena ? result.arena->family : std::nullopt);
  } catch (const std::exception& e) {
    result.mapProblems.push_back(std::string("cannot survey: ") + e.what());
    return result;
  }
  if (!result.survey.spawn) {
    result.mapProblems.push_back("no player spawn point");
    return result;
  }
  if (!result.survey.eyeInsideLevel())
    result.mapProblems.push_back("spawn eye in an opaque leaf (inside a wall or outside the level)");

  // One pa-render process renders the three over the map loaded once. The lightmap picture is
  // exposed automatically; direct and path with the lightmap's gain (pa-render's --exposure auto
  // with several integrators), so that they are judged against the baked light at the same
  // exposure (README.md).
  RenderRequest request;
  request.paRender = o.paRender;
  request.scene = o.gameDir / gamePath;
  for (const IntegratorRun& run : runs) request.integrators.push_back({run.name, run.spp});
  request.tonemap = "clamp";
  request.camera = result.survey.spawn->cameraIndex;
  request.exposure = o.fixedExposure ? *o.fixedExposure : "auto";
  request.width = o.width;
  request.height = o.height;
  request.threads = o.threads;
  request.outputStem = o.out / "renders" / result.map;
  request.reuseExisting = o.reuse;
  std::vector<RenderResult> renders = runPaRender(request);

  for (size_t k = 0; k < runs.size(); ++k) {
    RenderResult& rendered = renders[k];
    IntegratorOutcome outcome;
    outcome.integrator = runs[k].name;
    outcome.expectedBecause = knownProblemReason(known, result.map, runs[k].name).value_or(result.mapExpectedBecause);
    outcome.wallMilliseconds = rendered.wallMilliseconds;
    outcome.renderMilliseconds = rendered.renderMilliseconds;
    outcome.exposure = rendered.exposure;
    outcome.exposureAtMaxGain = rendered.exposureAtMaxGain;
    if (!rendered.ok()) {
      std::string log = rendered.exitCode != 0 ? rendered.log : "";   // its last line is the error message
      while (!log.empty() && log.back() == '\n') log.pop_back();
      outcome.problems.push_back(rendered.error + (log.empty() ? "" : " (" + log.substr(log.rfind('\n') + 1) + ")"));
    } else if (rendered.cameraName != result.survey.spawn->cameraName) {
      outcome.problems.push_back("pa-render used camera \"" + rendered.cameraName + "\", expected \"" +
                                 result.survey.spawn->cameraName + "\"");
    } else {
      outcome.rendered = true;
      outcome.stats = computeImageStats(rendered.image.pixels, rendered.depth, thresholds);
      outcome.unexposedStats = computeImageStats(rendered.unexposedImage.pixels, rendered.depth, thresholds);
      outcome.problems = implausibilityReasons(outcome.stats, thresholds, outcome.exposureAtMaxGain);
      result.triangles = rendered.triangles;
      result.lights = rendered.lights;
      images[k] = std::move(rendered.image);
    }
    result.renders.push_back(std::move(outcome));
  }
  return result;
}

/// The game's arena lists in the order the game reads them: scripts/arenas.txt, then
/// scripts/*.arena (a map's first entry counts). Problems are printed, not fatal.
ArenaIndex loadArenas(const q3::GameFileSystem& game) {
  ArenaIndex arenas;
  std::vector<std::string> files = {"scripts/arenas.txt"};
  for (const std::string& f : game.listFiles("scripts", ".arena")) files.push_back(f);
  std::vector<std::string> warnings;
  for (const std::string& file : files) {
    try {
      const auto bytes = game.readFile(file);
      if (!bytes) continue;
      arenas.addFile(std::string_view(reinterpret_cast<const char*>(bytes->data()), bytes->size()), file, warnings);
    } catch (const std::exception& e) {
      warnings.push_back(e.what());
    }
  }
  for (const std::string& w : warnings) std::printf("pa-all-maps: arena list: %s\n", w.c_str());
  return arenas;
}

/// One line per checked map on stdout: "[done/total] MAP ok|FAIL  integrator figures...".
void printProgress(const MapResult& result, size_t done, size_t total) {
  std::string line = result.failed() ? "FAIL" : "ok";
  for (const IntegratorOutcome& r : result.renders)
    if (r.rendered) {
      char text[128];
      std::snprintf(text, sizeof text, "  %s x%.2f lum %.3f (x1 %.3f) black %.0f%% sky %.0f%% %.0f ms",
                    r.integrator.c_str(), r.exposure, r.stats.meanLuma, r.unexposedStats.meanLuma,
                    100 * r.stats.blackFraction, 100 * r.stats.skyFraction, r.wallMilliseconds);
      line += text;
    }
  std::printf("[%zu/%zu] %-20s %s\n", done, total, result.map.c_str(), line.c_str());
  std::fflush(stdout);
}

ThumbVerdict thumbVerdict(const IntegratorOutcome& o) {
  if (!o.rendered) return ThumbVerdict::Missing;
  if (o.problems.empty()) return ThumbVerdict::Pass;
  return o.expectedBecause.empty() ? ThumbVerdict::Fail : ThumbVerdict::ExpectedFail;
}

int run(const Options& o) {
  if (!fs::is_directory(o.gameDir)) {
    std::printf("pa-all-maps: %s is not installed; skipping\n", o.gameDir.c_str());
    return kExitSkip;
  }
  std::vector<KnownProblem> known;
  if (!o.knownProblems.empty()) known = parseKnownProblems(readTextFile(o.knownProblems), o.knownProblems.string());

  const q3::GameFileSystem game(o.gameDir);
  const ArenaIndex arenas = loadArenas(game);
  std::vector<std::string> maps = game.listFiles("maps", ".bsp");
  if (maps.empty()) {
    std::printf("pa-all-maps: no maps in %s; skipping\n", o.gameDir.c_str());
    return kExitSkip;
  }
  if (!o.maps.empty()) {
    std::vector<std::string> chosen;
    for (const std::string& name : o.maps) {
      const std::string path = "maps/" + name + ".bsp";
      if (!game.exists(path)) {
        std::fprintf(stderr, "pa-all-maps: map \"%s\" is not in %s\n", name.c_str(), o.gameDir.c_str());
        return kExitFail;
      }
      chosen.push_back(path);
    }
    maps = chosen;
  }

  fs::create_directories(o.out);
  // Maps are checked by `jobs` workers at once (pa-render spends most of a call loading the map
  // on one core); results are kept in map order, so the reports do not depend on `jobs`.
  std::vector<MapResult> results(maps.size());
  std::vector<std::vector<RgbaImage>> images(maps.size());
  std::atomic<size_t> nextMap{0};
  std::mutex printing;
  size_t done = 0;
  auto worker = [&] {
    for (size_t i = nextMap++; i < maps.size(); i = nextMap++) {
      try {
        results[i] = checkMap(o, game, arenas, maps[i], known, images[i]);
      } catch (const std::exception& e) {
        results[i].map = mapName(maps[i]);
        results[i].mapProblems.push_back(std::string("cannot check: ") + e.what());
      }
      const std::lock_guard<std::mutex> lock(printing);
      printProgress(results[i], ++done, maps.size());
    }
  };
  std::vector<std::thread> workers;
  for (uint32_t j = 1; j < std::min<size_t>(o.jobs, maps.size()); ++j) workers.emplace_back(worker);
  worker();
  for (std::thread& w : workers) w.join();

  ContactSheet sheet(o.width, o.height, 3, o.columns);
  for (size_t i = 0; i < maps.size(); ++i) {
    std::vector<Thumb> thumbs;
    for (size_t k = 0; k < images[i].size(); ++k)
      thumbs.push_back({std::move(images[i][k]), k < results[i].renders.size() ? thumbVerdict(results[i].renders[k])
                                                                                : ThumbVerdict::Missing});
    sheet.addCell(results[i].map, thumbs);
  }


  std::ostringstream markdown;
  writeMarkdownReport(markdown, results, PlausibilityThresholds{});
  std::ofstream(o.out / "results.md") << markdown.str();
  std::ofstream tsv(o.out / "results.tsv");
  writeTsvReport(tsv, results);
  const RgbaImage contact = sheet.compose();
  const fs::path sheetPath = o.out / "contact_sheet.png";
  if (!stbi_write_png(sheetPath.c_str(), int(contact.width), int(contact.height), 4, contact.pixels.data(),
                      int(contact.width * 4)))
    std::fprintf(stderr, "pa-all-maps: %s: cannot write\n", sheetPath.c_str());

  std::printf("\n%s\nWrote %s, %s and %s\n", markdown.str().c_str(), (o.out / "results.md").c_str(),
              (o.out / "results.tsv").c_str(), sheetPath.c_str());
  size_t failed = 0;
  for (const MapResult& r : results) failed += r.failed() ? 1 : 0;
  std::printf("pa-all-maps: %zu of %zu maps failed\n", failed, results.size());
  return failed == 0 ? kExitPass : kExitFail;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  const std::string error = parseOptions(argc, argv, options);
  if (error == "help") {
    std::fputs(kUsage, stdout);
    return kExitPass;
  }
  if (!error.empty()) {
    std::fprintf(stderr, "pa-all-maps: %s\n%s", error.c_str(), kUsage);
    return kExitUsage;
  }
  try {
    return run(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pa-all-maps: error: %s\n", e.what());
    return kExitFail;
  }
}
