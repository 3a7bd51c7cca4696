// Contact sheet layout and a tiny 5x7 bitmap font for the labels.
#include "tests/all_maps_render/contact_sheet.h"

#include <algorithm>
#include <array>
#include <cctype>

namespace pa::allmaps {
namespace {

constexpr uint32_t kGlyphWidth = 5;
constexpr uint32_t kGlyphHeight = 7;
constexpr uint32_t kGlyphAdvance = kGlyphWidth + 1;
constexpr uint32_t kLabelHeight = kGlyphHeight + 4;
constexpr uint32_t kFrame = 2;        // frame thickness around each thumbnail
constexpr uint32_t kGap = 2;          // between thumbnails of a cell
constexpr uint32_t kCellMargin = 6;   // between cells

/// One glyph: 7 rows, bit 4 = leftmost column.
struct Glyph {
  char c;
  std::array<uint8_t, kGlyphHeight> rows;
};

// The classic 5x7 LCD character shapes.
constexpr Glyph kFont[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}}, {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}}, {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}}, {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}}, {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}}, {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}}, {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}}, {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}}, {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}}, {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}}, {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}}, {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}}, {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}}, {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}}, {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}}, {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}}, {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
    {' ', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}}, {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}}, {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}}, {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}},
    {'%', {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}}, {'!', {0x04, 0x04, 0x04, 0x04, 0x04, 0x00, 0x04}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}}, {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}},
};
constexpr Glyph kUnknownGlyph = {'?', {0x1F, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1F}};

const Glyph& glyphFor(char c) {
  const char upper = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const Glyph& g : kFont)
    if (g.c == upper) return g;
  return kUnknownGlyph;
}

void setPixel(RgbaImage& image, uint32_t x, uint32_t y, const uint8_t rgb[3]) {
  if (x >= image.width || y >= image.height) return;
  uint8_t* p = &image.pixels[(size_t{y} * image.width + x) * 4];
  p[0] = rgb[0];
  p[1] = rgb[1];
  p[2] = rgb[2];
  p[3] = 255;
}

void fillRect(RgbaImage& image, uint32_t x, uint32_t y, uint32_t w, uint32_t h, const uint8_t rgb[3]) {
  for (uint32_t j = 0; j < h; ++j)
    for (uint32_t i = 0; i < w; ++i) setPixel(image, x + i, y + j, rgb);
}

/// Nearest-neighbour copy of `source` into the w x h rectangle at (x, y).
void blitScaled(RgbaImage& target, uint32_t x, uint32_t y, uint32_t w, uint32_t h, const RgbaImage& source) {
  for (uint32_t j = 0; j < h; ++j) {
    const uint32_t sy = static_cast<uint32_t>(uint64_t{j} * source.height / h);
    for (uint32_t i = 0; i < w; ++i) {
      const uint32_t sx = static_cast<uint32_t>(uint64_t{i} * source.width / w);
      const uint8_t* p = &source.pixels[(size_t{sy} * source.width + sx) * 4];
      setPixel(target, x + i, y + j, p);
    }
  }
}

constexpr uint8_t kBackground[3] = {24, 24, 28};
constexpr uint8_t kLabelColour[3] = {230, 230, 230};
constexpr uint8_t kFailLabelColour[3] = {255, 90, 90};
constexpr uint8_t kPassFrame[3] = {90, 90, 96};
constexpr uint8_t kFailFrame[3] = {230, 30, 30};
constexpr uint8_t kExpectedFrame[3] = {255, 150, 0};
constexpr uint8_t kMissingFill[3] = {70, 0, 0};

bool validImage(const RgbaImage& image) {
  return image.width > 0 && image.height > 0 && image.pixels.size() == size_t{image.width} * image.height * 4;
}

}  // namespace

uint32_t textWidth(std::string_view text) {
  return text.empty() ? 0 : static_cast<uint32_t>(text.size()) * kGlyphAdvance - 1;
}

uint32_t drawText(RgbaImage& image, uint32_t x, uint32_t y, std::string_view text, const uint8_t rgb[3]) {
  for (char c : text) {
    const Glyph& g = glyphFor(c);
    for (uint32_t row = 0; row < kGlyphHeight; ++row)
      for (uint32_t col = 0; col < kGlyphWidth; ++col)
        if (g.rows[row] & (0x10u >> col)) setPixel(image, x + col, y + row, rgb);
    x += kGlyphAdvance;
  }
  return x;
}

ContactSheet::ContactSheet(uint32_t thumbWidth, uint32_t thumbHeight, uint32_t thumbsPerCell, uint32_t columns)
    : thumbWidth_(std::max(thumbWidth, 1u)),
      thumbHeight_(std::max(thumbHeight, 1u)),
      thumbsPerCell_(std::max(thumbsPerCell, 1u)),
      columns_(std::max(columns, 1u)) {}

void ContactSheet::addCell(std::string_view label, const std::vector<Thumb>& thumbs) {
  Cell cell{std::string(label), {}};
  for (uint32_t i = 0; i < thumbsPerCell_; ++i)
    cell.thumbs.push_back(i < thumbs.size() ? thumbs[i] : Thumb{RgbaImage{}, ThumbVerdict::Missing});
  cells_.push_back(std::move(cell));
}

RgbaImage ContactSheet::compose() const {
  const uint32_t framedWidth = thumbWidth_ + 2 * kFrame;
  const uint32_t framedHeight = thumbHeight_ + 2 * kFrame;
  const uint32_t cellWidth = thumbsPerCell_ * framedWidth + (thumbsPerCell_ - 1) * kGap;
  const uint32_t cellHeight = kLabelHeight + framedHeight;
  const uint32_t count = static_cast<uint32_t>(cells_.size());
  if (count == 0) return RgbaImage{1, 1, {kBackground[0], kBackground[1], kBackground[2], 255}};
  const uint32_t columns = std::min(columns_, count);
  const uint32_t rows = (count + columns - 1) / columns;

  RgbaImage sheet;
  sheet.width = kCellMargin + columns * (cellWidth + kCellMargin);
  sheet.height = kCellMargin + rows * (cellHeight + kCellMargin);
  sheet.pixels.assign(size_t{sheet.width} * sheet.height * 4, 255);
  fillRect(sheet, 0, 0, sheet.width, sheet.height, kBackground);

  const size_t maxChars = (cellWidth + 1) / kGlyphAdvance;
  for (uint32_t c = 0; c < count; ++c) {
    const Cell& cell = cells_[c];
    const uint32_t x0 = kCellMargin + (c % columns) * (cellWidth + kCellMargin);
    const uint32_t y0 = kCellMargin + (c / columns) * (cellHeight + kCellMargin);
    const bool anyFail = std::any_of(cell.thumbs.begin(), cell.thumbs.end(), [](const Thumb& t) {
      return t.verdict == ThumbVerdict::Fail || t.verdict == ThumbVerdict::Missing;
    });
    drawText(sheet, x0 + 1, y0 + 1, std::string_view(cell.label).substr(0, maxChars),
             anyFail ? kFailLabelColour : kLabelColour);
    for (uint32_t t = 0; t < thumbsPerCell_; ++t) {
      const Thumb& thumb = cell.thumbs[t];
      const uint32_t fx = x0 + t * (framedWidth + kGap);
      const uint32_t fy = y0 + kLabelHeight;
      const bool missing = thumb.verdict == ThumbVerdict::Missing || !validImage(thumb.image);
      const uint8_t* frame = missing                                        ? kFailFrame
                             : thumb.verdict == ThumbVerdict::Fail         ? kFailFrame
                             : thumb.verdict == ThumbVerdict::ExpectedFail ? kExpectedFrame
                                                                           : kPassFrame;
      fillRect(sheet, fx, fy, framedWidth, framedHeight, frame);
      if (missing) {
        fillRect(sheet, fx + kFrame, fy + kFrame, thumbWidth_, thumbHeight_, kMissingFill);
        for (uint32_t i = 0; i < thumbWidth_; ++i) {   // an X across the cell
          const uint32_t j = static_cast<uint32_t>(uint64_t{i} * thumbHeight_ / thumbWidth_);
          setPixel(sheet, fx + kFrame + i, fy + kFrame + j, kFailFrame);
          setPixel(sheet, fx + kFrame + i, fy + kFrame + thumbHeight_ - 1 - j, kFailFrame);
        }
      } else {
        blitScaled(sheet, fx + kFrame, fy + kFrame, thumbWidth_, thumbHeight_, thumb.image);
      }
    }
  }
  return sheet;
}

}  // namespace pa::allmaps
