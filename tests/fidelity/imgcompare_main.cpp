// pa-imgcompare A B [--diff OUT.png] [--gain G] [--min-psnr DB] [--min-ssim S] [--json] [--crop X,Y,W,H]
//                    [--flip-map OUT.png] [--ppd P]
// Compares two images of the same size (PNG, TGA, JPEG): PSNR over the R, G, B samples and
// SSIM on BT.601 luma with an 11x11 Gaussian window (sigma 1.5), see image_metrics.h.
// Prints "psnr_db=P ssim=S mse=M max_abs_diff=D luma_a=LA luma_b=LB luma_ratio=LB/LA
// worst_tile=X,Y worst_tile_psnr_db=T flip=F" (or one JSON object with --json); luma: mean linear
// luminance (meanLinearLuminance); worst tile: the 32x32 tile with the largest MSE (worstTile);
// flip: mean LDR-FLIP with A as the reference (flip.h) at P pixels per degree (default 67.02, the
// paper's 0.7 m from a 0.7 m wide 3840-pixel monitor); --flip-map writes its error map (grey).
// --crop compares only the W x H rectangle at (X, Y) (top-left origin) of both images.
// Exit 0: compared and above the thresholds; 1: below a threshold; 2: usage or file error.
#include "tests/fidelity/flip.h"
#include "tests/fidelity/image_metrics.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: pa-imgcompare A B [--diff OUT.png] [--gain G] [--min-psnr DB] [--min-ssim S] [--json] "
               "[--crop X,Y,W,H] [--flip-map OUT.png] [--ppd P]\n");
  return 2;
}

bool parseNumber(const char* text, double& value) {
  char* end = nullptr;
  value = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(value);
}

}  // namespace

int main(int argc, char** argv) {
  std::string pathA, pathB, diffPath, flipPath;
  double gain = 4, minPsnr = -1, minSsim = -2, ppd = pa::fidelity::flipDefaultPixelsPerDegree();
  bool json = false;
  int cropRect[4] = {0, 0, 0, 0};
  bool cropped = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool hasValue = i + 1 < argc;
    if (arg == "--diff" && hasValue) {
      diffPath = argv[++i];
    } else if (arg == "--flip-map" && hasValue) {
      flipPath = argv[++i];
    } else if (arg == "--ppd" && hasValue) {
      if (!parseNumber(argv[++i], ppd) || ppd <= 0) return usage();
    } else if (arg == "--gain" && hasValue) {
      if (!parseNumber(argv[++i], gain) || gain <= 0) return usage();
    } else if (arg == "--min-psnr" && hasValue) {
      if (!parseNumber(argv[++i], minPsnr)) return usage();
    } else if (arg == "--min-ssim" && hasValue) {
      if (!parseNumber(argv[++i], minSsim)) return usage();
    } else if (arg == "--crop" && hasValue) {
      if (std::sscanf(argv[++i], "%d,%d,%d,%d", &cropRect[0], &cropRect[1], &cropRect[2], &cropRect[3]) != 4)
        return usage();
      cropped = true;
    } else if (arg == "--json") {
      json = true;
    } else if (!arg.empty() && arg[0] != '-' && pathA.empty()) {
      pathA = arg;
    } else if (!arg.empty() && arg[0] != '-' && pathB.empty()) {
      pathB = arg;
    } else {
      return usage();
    }
  }
  if (pathA.empty() || pathB.empty()) return usage();
  try {
    auto a = pa::fidelity::loadRgb(pathA);
    auto b = pa::fidelity::loadRgb(pathB);
    if (cropped) {
      a = pa::fidelity::crop(a, cropRect[0], cropRect[1], cropRect[2], cropRect[3]);
      b = pa::fidelity::crop(b, cropRect[0], cropRect[1], cropRect[2], cropRect[3]);
    }
    const auto result = pa::fidelity::compare(a, b);
    if (!diffPath.empty()) pa::fidelity::savePng(diffPath, pa::fidelity::differenceImage(a, b, gain));
    // JSON has no infinity: identical images report psnr_db 999.
    const double psnr = std::isinf(result.psnr) ? 999.0 : result.psnr;
    const double lumaA = pa::fidelity::meanLinearLuminance(a), lumaB = pa::fidelity::meanLinearLuminance(b);
    const double lumaRatio = lumaA > 0.0 ? lumaB / lumaA : 0.0;   // B as bright as A: 1
    const auto tile = pa::fidelity::worstTile(a, b, 32);
    const double tilePsnr = std::isinf(tile.psnr) ? 999.0 : tile.psnr;
    const auto flipMap = pa::fidelity::flip(a, b, ppd);
    if (!flipPath.empty()) pa::fidelity::savePng(flipPath, pa::fidelity::flipErrorImage(flipMap));
    if (json)
      std::printf("{\"psnr_db\": %.3f, \"ssim\": %.5f, \"mse\": %.4f, \"max_abs_diff\": %.0f, \"width\": %d, \"height\": %d, "
                  "\"luma_a\": %.5f, \"luma_b\": %.5f, \"luma_ratio\": %.4f, \"worst_tile_x\": %d, \"worst_tile_y\": %d, "
                  "\"worst_tile_psnr_db\": %.3f, \"flip\": %.5f}\n",
                  psnr, result.ssim, result.mse, result.maxAbsDiff, a.width, a.height, lumaA, lumaB, lumaRatio, tile.x,
                  tile.y, tilePsnr, flipMap.mean);
    else
      std::printf("psnr_db=%.3f ssim=%.5f mse=%.4f max_abs_diff=%.0f luma_a=%.5f luma_b=%.5f luma_ratio=%.4f "
                  "worst_tile=%d,%d worst_tile_psnr_db=%.3f flip=%.5f\n",
                  psnr, result.ssim, result.mse, result.maxAbsDiff, lumaA, lumaB, lumaRatio, tile.x, tile.y, tilePsnr,
                  flipMap.mean);
    if (result.psnr < minPsnr || result.ssim < minSsim) {
      std::fprintf(stderr, "pa-imgcompare: below threshold (psnr %.3f < %.3f or ssim %.5f < %.5f)\n", psnr,
                   minPsnr, result.ssim, minSsim);
      return 1;
    }
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "pa-imgcompare: %s\n", error.what());
    return 2;
  }
}
