#include "renderer/image_codecs/jpeg_decode.h"

// jpeglib.h needs FILE and size_t declared first.
#include <cstdio>
// clang-format off
#include <jpeglib.h>
// clang-format on

#include <csetjmp>

namespace pa {
namespace {

/// libjpeg's error manager extended with the jump target of the running session. libjpeg reports
/// a fatal error by calling error_exit, which must not return: it jumps back to runLibjpeg.
/// Exceptions never cross libjpeg's C frames.
struct ErrorManager {
  jpeg_error_mgr pub;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void errorExit(j_common_ptr cinfo) {
  auto* err = reinterpret_cast<ErrorManager*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, err->message);
  std::longjmp(err->jump, 1);
}

/// Warnings (corrupt entropy-coded data, a premature end of file) are neither printed nor
/// fatal: libjpeg goes on as it does for the engine.
void ignoreMessage(j_common_ptr) {}

/// libjpeg's progress monitor with the scan limit.
struct ProgressMonitor {
  jpeg_progress_mgr pub;
  int maxScans;
};

/// Called by libjpeg while it consumes input: stops files with too many scans.
void checkScanCount(j_common_ptr cinfo) {
  auto* d = reinterpret_cast<j_decompress_ptr>(cinfo);
  const int maxScans = reinterpret_cast<ProgressMonitor*>(cinfo->progress)->maxScans;
  if (d->input_scan_number > maxScans) {
    auto* err = reinterpret_cast<ErrorManager*>(cinfo->err);
    std::snprintf(err->message, sizeof err->message, "more than %d scans", maxScans);
    std::longjmp(err->jump, 1);
  }
}

/// Plain data that outlives a longjmp: owned by the caller, so no destructor is skipped.
struct Session {
  jpeg_decompress_struct cinfo;
  ErrorManager err;
  ProgressMonitor progress;
  JpegLimits limits;
  int width = 0;
  int height = 0;
  bool headerRead = false;
  bool tooLarge = false;
};

/// stb_image's rounding of c * k / 255 (the inverted CMYK of Adobe files to RGB).
uint8_t multiply255(unsigned c, unsigned k) {
  const unsigned t = c * k + 128;
  return static_cast<uint8_t>((t + (t >> 8)) >> 8);
}

/// Reads the headers and, when `rgba` is given, the pixels. Returns false on a libjpeg error
/// (its message in s.err.message) or when the size is refused (s.tooLarge).
bool runLibjpeg(Session& s, std::span<const std::byte> bytes, std::vector<uint8_t>* rgba) {
  s.cinfo.err = jpeg_std_error(&s.err.pub);
  s.err.pub.error_exit = errorExit;
  s.err.pub.output_message = ignoreMessage;
  s.err.message[0] = '\0';
  if (setjmp(s.err.jump)) {
    jpeg_destroy_decompress(&s.cinfo);
    return false;
  }
  jpeg_create_decompress(&s.cinfo);
  s.progress.pub.progress_monitor = checkScanCount;
  s.progress.maxScans = s.limits.maxScans;
  s.cinfo.progress = &s.progress.pub;
  jpeg_mem_src(&s.cinfo, reinterpret_cast<const unsigned char*>(bytes.data()),
               static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&s.cinfo, TRUE);
  s.headerRead = true;
  s.width = static_cast<int>(s.cinfo.image_width);
  s.height = static_cast<int>(s.cinfo.image_height);
  if (rgba == nullptr) {
    jpeg_destroy_decompress(&s.cinfo);
    return true;
  }
  if (s.cinfo.image_width < 1 || s.cinfo.image_height < 1 ||
      s.cinfo.image_width > static_cast<JDIMENSION>(s.limits.maxDimension) ||
      s.cinfo.image_height > static_cast<JDIMENSION>(s.limits.maxDimension)) {
    s.tooLarge = true;
    jpeg_destroy_decompress(&s.cinfo);
    return false;
  }
  const bool cmyk = s.cinfo.jpeg_color_space == JCS_CMYK || s.cinfo.jpeg_color_space == JCS_YCCK;
  s.cinfo.out_color_space = cmyk ? JCS_CMYK : JCS_EXT_RGBA;
  jpeg_start_decompress(&s.cinfo);
  const size_t width = s.cinfo.output_width;
  try {
    rgba->resize(width * s.cinfo.output_height * 4);
  } catch (...) {
    jpeg_destroy_decompress(&s.cinfo);
    throw;
  }
  // libjpeg's own pool holds the CMYK row, so that it is freed with the session.
  JSAMPARRAY cmykRow = cmyk ? (*s.cinfo.mem->alloc_sarray)(reinterpret_cast<j_common_ptr>(&s.cinfo), JPOOL_IMAGE,
                                                           static_cast<JDIMENSION>(width * 4), 1)
                            : nullptr;
  while (s.cinfo.output_scanline < s.cinfo.output_height) {
    uint8_t* out = rgba->data() + static_cast<size_t>(s.cinfo.output_scanline) * width * 4;
    JSAMPROW row = cmyk ? cmykRow[0] : out;
    jpeg_read_scanlines(&s.cinfo, &row, 1);
    if (!cmyk) continue;
    for (size_t x = 0; x < width; ++x) {
      const unsigned k = row[x * 4 + 3];
      for (int c = 0; c < 3; ++c) out[x * 4 + c] = multiply255(row[x * 4 + c], k);
      out[x * 4 + 3] = 255;
    }
  }
  jpeg_finish_decompress(&s.cinfo);
  jpeg_destroy_decompress(&s.cinfo);
  return true;
}

uint8_t at(std::span<const std::byte> bytes, size_t i) { return static_cast<uint8_t>(bytes[i]); }

}  // namespace

bool isJpeg(std::span<const std::byte> bytes) {
  return bytes.size() >= 3 && at(bytes, 0) == 0xFF && at(bytes, 1) == 0xD8 && at(bytes, 2) == 0xFF;
}

std::array<int, 2> jpegSize(std::span<const std::byte> bytes) {
  Session s;
  if (!runLibjpeg(s, bytes, nullptr)) throw JpegError(JpegError::Stage::Header, s.err.message);
  return {s.width, s.height};
}

JpegImage decodeJpeg(std::span<const std::byte> bytes, const JpegLimits& limits) {
  Session s;
  s.limits = limits;
  JpegImage image;
  if (!runLibjpeg(s, bytes, &image.rgba)) {
    if (s.tooLarge)
      throw JpegError(JpegError::Stage::Size, std::to_string(s.width) + "x" + std::to_string(s.height) +
                                                  " outside 1.." + std::to_string(limits.maxDimension));
    throw JpegError(s.headerRead ? JpegError::Stage::Data : JpegError::Stage::Header, s.err.message);
  }
  image.width = s.width;
  image.height = s.height;
  return image;
}

}  // namespace pa
