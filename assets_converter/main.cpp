// assets_converter: Quake III maps (.bsp inside .pk3 archives) -> binary glTF 2.0.
//   assets_converter --game DIR (--map NAME ... | --all) -o OUTDIR [options]
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "assets_converter/map_conversion.h"

namespace {

constexpr const char* kUsage =
    "usage: assets_converter --game DIR (--map NAME [--map NAME ...] | --all) -o OUTDIR [options]\n"
    "  --game DIR        game folder with .pk3 archives (e.g. /usr/share/games/openarena/baseoa)\n"
    "  --map NAME        map to convert: oa_dm1, oa_dm1.bsp or maps/oa_dm1.bsp (repeatable)\n"
    "  --all             every maps/*.bsp of the game folder\n"
    "  --list            print the maps of the game folder and exit\n"
    "  -o, --out OUTDIR  where NAME.glb files are written (created if missing)\n"
    "  --scale M         metres per Quake unit (default 0.03125 = 1/32; 0.0254 = inch)\n"
    "  --no-lightmaps    leave out lightmap images and TEXCOORD_1\n"
    "  --no-lights       leave out KHR_lights_punctual lights\n"
    "  --no-cameras      leave out spawn-point cameras\n"
    "  --keep-sky        keep the sky box brushes (hidden by default)\n"
    "  --warnings        print every content warning (missing textures, bad entity keys)\n";

struct Arguments {
  std::string game;
  std::vector<std::string> maps;
  bool all = false;
  bool list = false;
  bool printWarnings = false;
  std::filesystem::path out;
  pa::converter::ExportOptions options;
};

[[noreturn]] void usageError(const std::string& message) {
  std::cerr << "assets_converter: " << message << "\n" << kUsage;
  std::exit(2);
}

Arguments parseArguments(int argc, char** argv) {
  Arguments args;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usageError(a + " needs a value");
      return argv[++i];
    };
    if (a == "--game") args.game = value();
    else if (a == "--map") args.maps.push_back(value());
    else if (a == "--all") args.all = true;
    else if (a == "--list") args.list = true;
    else if (a == "-o" || a == "--out") args.out = value();
    else if (a == "--scale") {
      std::string v = value();
      char* end = nullptr;
      float scale = std::strtof(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !(scale > 0.0f) || scale > 1000.0f) usageError("bad --scale " + v);
      args.options.metresPerUnit = scale;
    } else if (a == "--no-lightmaps") args.options.lightmaps = false;
    else if (a == "--no-lights") args.options.lights = false;
    else if (a == "--no-cameras") args.options.cameras = false;
    else if (a == "--keep-sky") args.options.skySurfaces = true;
    else if (a == "--warnings") args.printWarnings = true;
    else if (a == "-h" || a == "--help") {
      std::cout << kUsage;
      std::exit(0);
    } else usageError("unknown argument " + a);
  }
  if (args.game.empty()) usageError("--game is required");
  if (args.list) return args;
  if (args.maps.empty() && !args.all) usageError("give --map NAME or --all");
  if (args.out.empty()) usageError("-o OUTDIR is required");
  return args;
}

void drawProgress(size_t done, size_t total, const std::string& current) {
  constexpr int kWidth = 30;
  int filled = total ? int(kWidth * done / total) : kWidth;
  std::string bar(size_t(filled), '=');
  if (filled < kWidth) bar += '>' + std::string(size_t(kWidth - filled - 1), ' ');
  std::fprintf(stderr, "\r[%s] %zu/%zu %-40.40s", bar.c_str(), done, total, current.c_str());
  std::fflush(stderr);
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args = parseArguments(argc, argv);
  std::unique_ptr<pa::converter::GameData> game;
  try {
    game = std::make_unique<pa::converter::GameData>(args.game);
  } catch (const std::exception& e) {
    std::cerr << "assets_converter: " << e.what() << "\n";
    return 1;
  }
  for (const std::string& error : game->files.mountErrors()) std::cerr << "warning: " << error << "\n";
  for (const std::string& error : game->scriptErrors) std::cerr << "warning: shader script ignored: " << error << "\n";

  std::vector<std::string> maps = args.maps;
  if (args.all || args.list) {
    std::vector<std::string> found = pa::converter::listMaps(game->files);
    if (args.list) {
      for (const std::string& m : found) std::cout << m << "\n";
      return 0;
    }
    maps.insert(maps.end(), found.begin(), found.end());
  }
  if (maps.empty()) {
    std::cerr << "assets_converter: no maps in " << args.game << "\n";
    return 1;
  }

  const bool batch = maps.size() > 1;
  std::vector<pa::converter::MapResult> results;
  for (size_t i = 0; i < maps.size(); ++i) {
    if (batch) drawProgress(i, maps.size(), maps[i]);
    results.push_back(pa::converter::convertMap(*game, maps[i], args.out, args.options));
  }
  if (batch) {
    drawProgress(maps.size(), maps.size(), "done");
    std::fputc('\n', stderr);
  }

  int failures = 0;
  double totalSeconds = 0.0;
  uint64_t totalTriangles = 0;
  std::printf("%-28s %10s %9s %6s %7s %8s %8s %8s\n", "map", "triangles", "materials", "lights", "cameras", "MiB",
              "warnings", "seconds");
  for (const auto& r : results) {
    totalSeconds += r.seconds;
    if (!r.error.empty()) {
      ++failures;
      std::printf("%-28s FAILED: %s\n", r.map.c_str(), r.error.c_str());
      continue;
    }
    totalTriangles += r.stats.triangles;
    std::printf("%-28s %10llu %9u %6u %7u %8.2f %8zu %8.3f\n", r.map.c_str(), (unsigned long long)r.stats.triangles,
                r.stats.materials, r.stats.lights, r.stats.cameras, double(r.stats.bytes) / (1024.0 * 1024.0),
                r.warnings.size(), r.seconds);
    if (args.printWarnings)
      for (const auto& w : r.warnings) std::printf("    warning: %s\n", w.c_str());
  }
  std::printf("%-28s %10llu %9s %6s %7s %8s %8s %8.3f\n", "total", (unsigned long long)totalTriangles, "", "", "", "", "",
              totalSeconds);
  if (failures) std::fprintf(stderr, "%d of %zu maps failed\n", failures, results.size());
  return failures ? 1 : 0;
}
