// shot_check FILE.png [--no-world]: checks an in-game screenshot. Exit 0 when
//  - the picture is not black,
//  - the HUD band (bottom 20% of the picture) has bright, saturated pixels (numbers, icons),
//  - the 3D view (the middle of the picture) shows a world: many distinct colours and
//    at least a quarter of non-black pixels (skipped with --no-world).
// Prints the measured figures either way.
#include <stb_image.h>

#include <cstdio>
#include <cstring>
#include <set>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: shot_check FILE.png [--no-world]\n");
    return 2;
  }
  const bool checkWorld = !(argc >= 3 && std::strcmp(argv[2], "--no-world") == 0);
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load(argv[1], &w, &h, &channels, 3);
  if (pixels == nullptr) {
    std::fprintf(stderr, "shot_check: cannot read %s: %s\n", argv[1], stbi_failure_reason());
    return 1;
  }
  auto at = [&](int x, int y) { return pixels + (static_cast<size_t>(y) * w + x) * 3; };
  long nonBlack = 0, hudBright = 0, hudPixels = 0, viewNonBlack = 0, viewPixels = 0;
  std::set<unsigned> viewColours;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const unsigned char* p = at(x, y);
      const int sum = p[0] + p[1] + p[2];
      if (sum > 30) ++nonBlack;
      if (y >= h * 8 / 10) {
        ++hudPixels;
        if (sum > 300) ++hudBright;
      } else if (y >= h / 10 && y < h * 7 / 10 && x >= w / 10 && x < w * 9 / 10) {
        ++viewPixels;
        if (sum > 30) ++viewNonBlack;
        viewColours.insert((p[0] >> 3) << 10 | (p[1] >> 3) << 5 | (p[2] >> 3));
      }
    }
  stbi_image_free(pixels);
  const double nonBlackFraction = double(nonBlack) / (double(w) * h);
  const double hudFraction = double(hudBright) / double(hudPixels);
  const double viewFraction = double(viewNonBlack) / double(viewPixels);
  std::printf("shot_check %s: %dx%d non-black %.3f, HUD bright %.4f, view non-black %.3f, "
              "view colours %zu\n", argv[1], w, h, nonBlackFraction, hudFraction, viewFraction,
              viewColours.size());
  bool ok = true;
  if (nonBlackFraction < 0.01) { std::printf("FAIL: picture is black\n"); ok = false; }
  if (hudFraction < 0.002) { std::printf("FAIL: no HUD pixels in the bottom band\n"); ok = false; }
  if (checkWorld && (viewFraction < 0.25 || viewColours.size() < 64)) {
    std::printf("FAIL: the 3D view shows no world\n");
    ok = false;
  }
  return ok ? 0 : 1;
}
