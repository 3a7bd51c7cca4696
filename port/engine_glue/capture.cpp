// Console commands and frame capture: screenshot / screenshotJPEG / screenshotPNG (written
// through ri.FS_WriteFile as screenshots/shotNNNN.ext, the engine's naming), levelshots, and
// TakeVideoFrame for the engine's `video` AVI recorder.
#include <stb_image_write.h>

#include <algorithm>
#include <cstring>

#include "port/engine_glue/allocation_counter.h"
#include "port/engine_glue/module.h"

namespace glue {

void runCommand(const char* name, void (*handler)(Module&));   // module_entry.cpp

namespace {

void appendBytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  const auto* bytes = static_cast<const uint8_t*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

/// Encodes top-first RGB rows as TGA, JPEG or PNG.
std::vector<uint8_t> encode(const std::string& extension, const std::vector<uint8_t>& rgb,
                            int width, int height) {
  std::vector<uint8_t> file;
  if (extension == "png")
    stbi_write_png_to_func(appendBytes, &file, width, height, 3, rgb.data(), width * 3);
  else if (extension == "jpg")
    stbi_write_jpg_to_func(appendBytes, &file, width, height, 3, rgb.data(), 90);
  else
    stbi_write_tga_to_func(appendBytes, &file, width, height, 3, rgb.data());
  return file;
}

/// Box-filters top-first RGB down to size x size (levelshots).
std::vector<uint8_t> shrink(const std::vector<uint8_t>& rgb, int width, int height, int size) {
  std::vector<uint8_t> out(static_cast<size_t>(size) * size * 3);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const int x0 = x * width / size, x1 = std::max(x0 + 1, (x + 1) * width / size);
      const int y0 = y * height / size, y1 = std::max(y0 + 1, (y + 1) * height / size);
      for (int c = 0; c < 3; ++c) {
        unsigned sum = 0, count = 0;
        for (int yy = y0; yy < y1; ++yy)
          for (int xx = x0; xx < x1; ++xx, ++count) sum += rgb[(size_t(yy) * width + xx) * 3 + c];
        out[(size_t(y) * size + x) * 3 + c] = static_cast<uint8_t>(sum / std::max(count, 1u));
      }
    }
  return out;
}

}  // namespace

void Module::addCommands() {
  if (commandsAdded_) return;
  const auto& ri = engine_.ri();
  ri.Cmd_AddCommand("screenshot", [] {
    runCommand("screenshot", [](Module& m) { m.screenshotCommand("tga"); });
  });
  ri.Cmd_AddCommand("screenshotJPEG", [] {
    runCommand("screenshotJPEG", [](Module& m) { m.screenshotCommand("jpg"); });
  });
  ri.Cmd_AddCommand("screenshotPNG", [] {
    runCommand("screenshotPNG", [](Module& m) { m.screenshotCommand("png"); });
  });
  ri.Cmd_AddCommand("pt_allocations", [] {
    runCommand("pt_allocations", [](Module& m) { m.allocationsCommand(); });
  });
  commandsAdded_ = true;
}

void Module::removeCommands() {
  if (!commandsAdded_) return;
  const auto& ri = engine_.ri();
  ri.Cmd_RemoveCommand("screenshot");
  ri.Cmd_RemoveCommand("screenshotJPEG");
  ri.Cmd_RemoveCommand("screenshotPNG");
  ri.Cmd_RemoveCommand("pt_allocations");
  commandsAdded_ = false;
}

void Module::allocationsCommand() {
  const uint64_t count = allocationCount();
  // One line that tests/engine/engine_allocations.sh parses.
  engine_.print(q3abi::PRINT_ALL, "pathtracer: allocations=%llu frames=%llu\n",
                static_cast<unsigned long long>(count - allocationsMark_),
                static_cast<unsigned long long>(framesEnded_ - framesMark_));
  if (engine_.argc() >= 3 && engine_.argv(1) == "trace")
    traceNextAllocations(static_cast<uint32_t>(std::clamp(std::atoi(engine_.argv(2).c_str()), 0, 100000)));
  // The next window starts after this command's own allocations (the print, the arguments).
  allocationsMark_ = allocationCount();
  framesMark_ = framesEnded_;
}

void Module::screenshotCommand(const char* extension) {
  ScreenshotRequest request;
  request.extension = extension;
  if (engine_.argc() >= 2) {
    const std::string argument = engine_.argv(1);
    if (argument == "silent") {
      request.silent = true;
    } else if (argument == "levelshot") {
      request.levelshot = true;
    } else {
      // An explicit name: keep it inside screenshots/, without path tricks.
      std::string safe;
      for (char c : argument)
        if (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-') safe += c;
      if (safe.empty()) {
        engine_.warn("screenshot: bad file name '" + argument + "'");
        return;
      }
      request.fileName = "screenshots/" + safe + "." + request.extension;
    }
  }
  if (request.levelshot && !world_) {
    engine_.warn("levelshot: no map loaded");
    return;
  }
  // Between frames the back buffer still holds the frame just finished (it was swapped, not
  // cleared): read it now, as the stock renderer's screenshot command does. Inside a frame the
  // picture is not complete yet: capture at EndFrame.
  if (frameOpen_) pendingShots_.push_back(std::move(request));
  else takeScreenshot(request);
}

std::string Module::nextScreenshotName(const std::string& extension) {
  for (int number = lastShotNumber_; number <= 9999; ++number) {
    char name[64];
    std::snprintf(name, sizeof name, "screenshots/shot%04d.%s", number, extension.c_str());
    if (!engine_.fileExists(name)) {
      lastShotNumber_ = number + 1;
      return name;
    }
  }
  return {};
}

void Module::takeScreenshot(const ScreenshotRequest& request) {
  const int width = window_.width(), height = window_.height();
  std::vector<uint8_t> rgb = overlay_.readPixelsRGB(width, height);
  if (rgb.empty()) return;
  std::string name;
  std::vector<uint8_t> file;
  if (request.levelshot) {
    // levelshots/NAME.tga, 128x128, for the map menus.
    std::string map = world_->name();
    if (const size_t slash = map.find_last_of('/'); slash != std::string::npos) map.erase(0, slash + 1);
    name = "levelshots/" + stripExtension(map) + ".tga";
    file = encode("tga", shrink(rgb, width, height, 128), 128, 128);
  } else {
    name = request.fileName.empty() ? nextScreenshotName(request.extension) : request.fileName;
    if (name.empty()) {
      engine_.warn("screenshot: no free screenshots/shotNNNN name");
      return;
    }
    file = encode(request.extension, rgb, width, height);
  }
  if (file.empty()) {
    engine_.warn("screenshot: encoding " + name + " failed");
    return;
  }
  engine_.writeFile(name, file.data(), file.size());
  if (!request.silent) engine_.print(q3abi::PRINT_ALL, "Wrote %s\n", name.c_str());
  // r_pt_captureExr: the world view's film beside the picture (NAME.exr), for noise-aware checks.
  if (!request.levelshot && !filmCapture_.empty() && settings_.tracer(engine_).captureExr) {
    const std::vector<uint8_t> exr = encodeFilmExr(filmCapture_);
    if (exr.empty()) engine_.warn("screenshot: encoding the film of " + name + " as EXR failed");
    else engine_.writeFile(stripExtension(name) + ".exr", exr.data(), exr.size());
  }
}

void Module::takeVideoFrame(int width, int height, q3abi::byte* captureBuffer,
                            q3abi::byte* encodeBuffer, bool motionJpeg) {
  // The engine asks before drawing the frame: capture it at EndFrame, like the stock back end.
  if (captureBuffer == nullptr || encodeBuffer == nullptr || width <= 0 || height <= 0) return;
  pendingVideo_ = VideoFrameRequest{width, height, encodeBuffer, motionJpeg};
}

void Module::captureVideoFrame(const VideoFrameRequest& request) {
  const int width = std::min(request.width, window_.width());
  const int height = std::min(request.height, window_.height());
  const bool motionJpeg = request.motionJpeg;
  q3abi::byte* encodeBuffer = request.encodeBuffer;
  if (width <= 0 || height <= 0) return;
  const std::vector<uint8_t> full = overlay_.readPixelsRGB(window_.width(), window_.height());
  if (motionJpeg) {
    std::vector<uint8_t> rgb(static_cast<size_t>(width) * height * 3);
    for (int y = 0; y < height; ++y)
      std::memcpy(&rgb[size_t(y) * width * 3], &full[size_t(y) * window_.width() * 3],
                  size_t(width) * 3);
    const std::vector<uint8_t> jpeg = encode("jpg", rgb, width, height);
    // The engine sized encodeBuffer for a raw frame (width*height*4): a JPEG always fits.
    if (jpeg.size() > static_cast<size_t>(width) * height * 4) return;
    std::memcpy(encodeBuffer, jpeg.data(), jpeg.size());
    engine_.ri().CL_WriteAVIVideoFrame(encodeBuffer, static_cast<int>(jpeg.size()));
    return;
  }
  // Uncompressed AVI: BGR rows, bottom row first, each padded to 4 bytes.
  const size_t rowBytes = (static_cast<size_t>(width) * 3 + 3) & ~size_t(3);
  for (int y = 0; y < height; ++y) {
    const uint8_t* source = &full[size_t(height - 1 - y) * window_.width() * 3];
    uint8_t* target = encodeBuffer + size_t(y) * rowBytes;
    for (int x = 0; x < width; ++x) {
      target[x * 3 + 0] = source[x * 3 + 2];
      target[x * 3 + 1] = source[x * 3 + 1];
      target[x * 3 + 2] = source[x * 3 + 0];
    }
    std::memset(target + size_t(width) * 3, 0, rowBytes - size_t(width) * 3);
  }
  engine_.ri().CL_WriteAVIVideoFrame(encodeBuffer, static_cast<int>(rowBytes * height));
}

}  // namespace glue
