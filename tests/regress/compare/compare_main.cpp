// pa-regress-compare: compares one new frame with its reference for pa-regress and prints the
// figures as JSON; see tests/regress/README.md.
//   pa-regress-compare images NEW.png REF.png [options]   exit 0 pass, 1 fail, 2 error
//   pa-regress-compare convert IN.tga OUT.png             any stb-readable image to PNG
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <optional>
#include <string>

#include "tests/fidelity/image_metrics.h"
#include "tests/regress/compare/flip.h"
#include "tests/regress/compare/heat_map.h"
#include "tests/regress/compare/noise_test.h"

namespace {

using pa::fidelity::RgbImage;

const char* kUsage =
    "usage: pa-regress-compare images NEW.png REF.png [--mode exact|noise|perceptual]\n"
    "         [--new-exr NEW.exr --ref-exr REF.exr] [--alpha A] [--min-pass F]\n"
    "         [--flip-threshold T] [--fail-fraction F] [--min-psnr DB] [--min-ssim S]\n"
    "         [--diff OUT.png] [--heat OUT.png]\n"
    "       pa-regress-compare convert IN OUT.png\n"
    "modes: exact = identical pixels; noise = per-pixel Welch Z-test on the EXRs' mean luminance\n"
    "(Sidak-corrected at family level A, default 0.01; passes when >= F of the pixels pass, default\n"
    "0.9975); perceptual = LDR-FLIP: fails when more than F (default 0.01) of the pixels exceed T\n"
    "(default 0.1), and PSNR/SSIM under their minimum (when given) fail too.\n";

struct Options {
  std::string newPng, refPng, mode = "perceptual";
  std::optional<std::string> newExr, refExr, diffOut, heatOut;
  double alpha = 0.01, minPass = 0.9975, flipThreshold = 0.1, failFraction = 0.01;
  std::optional<double> minPsnr, minSsim;
};

double finiteOr(double v, double fallback) { return std::isfinite(v) ? v : fallback; }

int runImages(const Options& o) {
  const RgbImage fresh = pa::fidelity::loadRgb(o.newPng);
  const RgbImage ref = pa::fidelity::loadRgb(o.refPng);
  nlohmann::json out = {{"mode", o.mode}, {"width", fresh.width}, {"height", fresh.height}};
  if (fresh.width != ref.width || fresh.height != ref.height) {
    out["pass"] = false;
    out["reasons"] = {"size " + std::to_string(fresh.width) + "x" + std::to_string(fresh.height) + " != reference " +
                      std::to_string(ref.width) + "x" + std::to_string(ref.height)};
    std::cout << out.dump() << "\n";
    return 1;
  }
  const bool identical = fresh.pixels == ref.pixels;
  const auto metrics = pa::fidelity::compare(fresh, ref);
  const std::vector<float> flip = pa::regress::flipErrorMap(ref.pixels, fresh.pixels, ref.width, ref.height);
  double flipSum = 0, flipMax = 0;
  size_t flipOver = 0;
  for (float e : flip) {
    flipSum += e;
    flipMax = std::max<double>(flipMax, e);
    if (e > o.flipThreshold) ++flipOver;
  }
  const double flipFailFraction = static_cast<double>(flipOver) / static_cast<double>(flip.size());
  out["identical"] = identical;
  out["psnr"] = finiteOr(metrics.psnr, 999.0);
  out["ssim"] = metrics.ssim;
  out["max_abs_diff"] = metrics.maxAbsDiff;
  out["flip_mean"] = flipSum / static_cast<double>(flip.size());
  out["flip_max"] = flipMax;
  out["flip_threshold"] = o.flipThreshold;
  out["flip_fail_fraction"] = flipFailFraction;

  std::vector<std::string> reasons;
  std::vector<float> heat = flip;
  float heatScale = 1.0f;
  int heatWidth = ref.width, heatHeight = ref.height;   // the EXR's size in noise mode (a game's world film)
  if (o.mode == "exact") {
    if (!identical) reasons.push_back("pixels differ (exact); max |diff| " + std::to_string(static_cast<int>(metrics.maxAbsDiff)));
  } else if (o.mode == "noise") {
    if (!o.newExr || !o.refExr) throw std::invalid_argument("--mode noise needs --new-exr and --ref-exr");
    const pa::regress::HdrImage refHdr = pa::regress::loadExr(*o.refExr);
    const auto result = pa::regress::noiseTest(pa::regress::loadExr(*o.newExr), refHdr, {o.alpha, o.minPass});
    heatWidth = refHdr.width;
    heatHeight = refHdr.height;
    out["noise"] = {{"pixels", result.pixels},           {"failed_pixels", result.failedPixels},
                    {"pass_fraction", result.passFraction}, {"min_pass_fraction", o.minPass},
                    {"alpha", o.alpha},                  {"pixel_alpha", result.pixelAlpha},
                    {"z_threshold", result.zThreshold},  {"mean_abs_z", result.meanAbsZ}};
    nlohmann::json scales = nlohmann::json::array();
    for (const auto& s : result.scales) {
      scales.push_back({{"tile", s.tileSize}, {"tiles", s.tiles}, {"failed_tiles", s.failedTiles},
                        {"z_threshold", s.zThreshold}, {"max_abs_z", s.maxAbsZ}});
      if (s.failedTiles > 0)
        reasons.push_back("noise-aware test: " + std::to_string(s.failedTiles) + " of " + std::to_string(s.tiles) +
                          (s.tileSize > 0 ? " tiles of " + std::to_string(s.tileSize) + "x" + std::to_string(s.tileSize) : std::string(" whole image")) +
                          " beyond |z| " + std::to_string(s.zThreshold) + " (max " + std::to_string(s.maxAbsZ) + ")");
    }
    out["noise"]["tile_scales"] = scales;
    if (result.passFraction < o.minPass)
      reasons.push_back("noise-aware test: " + std::to_string(result.failedPixels) + " of " + std::to_string(result.pixels) +
                        " pixels beyond |z| " + std::to_string(result.zThreshold));
    heat = result.z;
    heatScale = static_cast<float>(2.0 * result.zThreshold);  // full scale: twice the threshold
  } else if (o.mode == "perceptual") {
    if (flipFailFraction > o.failFraction)
      reasons.push_back("FLIP: " + std::to_string(flipFailFraction) + " of the pixels above " + std::to_string(o.flipThreshold) +
                        " (allowed " + std::to_string(o.failFraction) + ")");
  } else {
    throw std::invalid_argument("unknown --mode " + o.mode);
  }
  if (o.minPsnr && metrics.psnr < *o.minPsnr) reasons.push_back("PSNR " + std::to_string(metrics.psnr) + " dB < " + std::to_string(*o.minPsnr));
  if (o.minSsim && metrics.ssim < *o.minSsim) reasons.push_back("SSIM " + std::to_string(metrics.ssim) + " < " + std::to_string(*o.minSsim));
  out["pass"] = reasons.empty();
  out["reasons"] = reasons;
  if (o.diffOut) pa::fidelity::savePng(*o.diffOut, pa::fidelity::differenceImage(fresh, ref, 16.0));
  if (o.heatOut) pa::fidelity::savePng(*o.heatOut, pa::regress::heatMap(heat, heatWidth, heatHeight, heatScale));
  std::cout << out.dump() << "\n";
  return reasons.empty() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc >= 2 && (!std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "--help"))) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if (argc == 4 && !std::strcmp(argv[1], "convert")) {
      pa::fidelity::savePng(argv[3], pa::fidelity::loadRgb(argv[2]));
      return 0;
    }
    if (argc < 4 || std::strcmp(argv[1], "images") != 0) {
      std::fputs(kUsage, stderr);
      return 2;
    }
    Options o;
    o.newPng = argv[2];
    o.refPng = argv[3];
    for (int i = 4; i < argc; ++i) {
      const std::string arg = argv[i];
      if (i + 1 >= argc) throw std::invalid_argument("missing value after " + arg);
      const std::string value = argv[++i];
      if (arg == "--mode") o.mode = value;
      else if (arg == "--new-exr") o.newExr = value;
      else if (arg == "--ref-exr") o.refExr = value;
      else if (arg == "--alpha") o.alpha = std::stod(value);
      else if (arg == "--min-pass") o.minPass = std::stod(value);
      else if (arg == "--flip-threshold") o.flipThreshold = std::stod(value);
      else if (arg == "--fail-fraction") o.failFraction = std::stod(value);
      else if (arg == "--min-psnr") o.minPsnr = std::stod(value);
      else if (arg == "--min-ssim") o.minSsim = std::stod(value);
      else if (arg == "--diff") o.diffOut = value;
      else if (arg == "--heat") o.heatOut = value;
      else throw std::invalid_argument("unknown option " + arg);
    }
    return runImages(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pa-regress-compare: %s\n", e.what());
    return 2;
  }
}
