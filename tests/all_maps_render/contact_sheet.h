#pragma once
// A contact sheet: labelled cells of thumbnails on one image, with a coloured frame per
// thumbnail saying whether its checks passed.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace pa::allmaps {

/// An 8-bit RGBA image, rows top to bottom.
struct RgbaImage {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> pixels;   ///< width * height * 4 bytes.
};

/// Verdict shown as the frame colour around a thumbnail.
enum class ThumbVerdict : uint8_t {
  Pass,          ///< Grey frame.
  Fail,          ///< Red frame.
  ExpectedFail,  ///< Orange frame: failed, and listed as a known problem.
  Missing,       ///< No image (render failed): a dark red cell with an X.
};

/// One thumbnail of a cell.
struct Thumb {
  RgbaImage image;                    ///< Empty (0x0) = missing, drawn as Missing.
  ThumbVerdict verdict = ThumbVerdict::Pass;
};

/// Lays out cells of `thumbsPerCell` thumbnails side by side under a one-line label.
class ContactSheet {
 public:
  /// Thumbnails are scaled (nearest) to thumbWidth x thumbHeight; `columns` cells per row.
  ContactSheet(uint32_t thumbWidth, uint32_t thumbHeight, uint32_t thumbsPerCell, uint32_t columns);

  /// Appends a cell; `thumbs` must hold thumbsPerCell entries (extra ones are ignored, missing
  /// ones drawn as Missing). The label is upper-cased and cut to the cell width.
  void addCell(std::string_view label, const std::vector<Thumb>& thumbs);

  /// The whole sheet (dark background). Empty sheet: a 1x1 image.
  RgbaImage compose() const;

 private:
  struct Cell {
    std::string label;
    std::vector<Thumb> thumbs;
  };
  uint32_t thumbWidth_;
  uint32_t thumbHeight_;
  uint32_t thumbsPerCell_;
  uint32_t columns_;
  std::vector<Cell> cells_;
};

/// Draws `text` with the built-in 5x7 font (A-Z, 0-9, space and _ - . : / % ! ( ) +; lower case
/// drawn as upper case, anything else as a box) at (x, y), clipped to the image. Returns the
/// x just after the text.
uint32_t drawText(RgbaImage& image, uint32_t x, uint32_t y, std::string_view text, const uint8_t rgb[3]);

/// Width in pixels of `text` drawn by drawText.
uint32_t textWidth(std::string_view text);

}  // namespace pa::allmaps
