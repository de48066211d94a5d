// The raster primitives and the bitmap font of scenarios/output/raster.h.
#include "scenarios/output/raster.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>

#include "core/types/image.h"
#include "scenarios/output/png.h"
#include "tests/support/run_pavilion.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

const Rgb kInk = {10, 20, 30};

bool IsInk(const core::RgbImage& image, int x, int y) {
  const std::size_t i = (static_cast<std::size_t>(y) * image.width + x) * 3;
  return image.pixels[i] == kInk[0] && image.pixels[i + 1] == kInk[1] &&
         image.pixels[i + 2] == kInk[2];
}

// Counts inked pixels inside and outside the box [x0, x0 + w) x [y0, y0 + h).
void CountInk(const core::RgbImage& image, int x0, int y0, int w, int h, int* inside,
              int* outside) {
  *inside = 0;
  *outside = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (!IsInk(image, x, y)) continue;
      const bool in = x >= x0 && x < x0 + w && y >= y0 && y < y0 + h;
      ++(in ? *inside : *outside);
    }
  }
}

// Text is drawn inside its measured box, touches all four sides of it (a
// caption with capitals, descenders and '|'), and nowhere else; a PNG of it is written.
TEST(RasterTest, TextFillsItsMeasuredBoxOnly) {
  const std::string longest = "scans.bin  scan 3 (pyg/front)  7 lines";
  const std::string text = longest + "\n\"GcceOH\" |C|=1.2e-05 A_q";
  const int columns = static_cast<int>(longest.size());
  for (const int scale : {1, 2, 3}) {
    SCOPED_TRACE(scale);
    const TextExtent size = MeasureText(text, scale);
    EXPECT_EQ(size.width_px, scale * ((columns - 1) * kGlyphAdvancePx + kGlyphWidthPx));
    EXPECT_EQ(size.height_px, scale * (kLineAdvancePx + kGlyphHeightPx));  // 2 lines
    core::RgbImage image(size.width_px + 40, size.height_px + 30);
    const int x0 = 17, y0 = 11;
    DrawText(&image, x0, y0, text, scale, kInk);
    int inside = 0, outside = 0;
    CountInk(image, x0, y0, size.width_px, size.height_px, &inside, &outside);
    EXPECT_GT(inside, 100 * scale * scale);
    EXPECT_EQ(outside, 0);
    bool left = false, right = false, top = false, bottom = false;
    for (int y = y0; y < y0 + size.height_px; ++y) {
      left = left || IsInk(image, x0, y);
      right = right || IsInk(image, x0 + size.width_px - 1, y);
    }
    for (int x = x0; x < x0 + size.width_px; ++x) {
      top = top || IsInk(image, x, y0);
      bottom = bottom || IsInk(image, x, y0 + size.height_px - 1);
    }
    EXPECT_TRUE(left && right && top && bottom);
    if (scale == 2) {
      const std::filesystem::path png = pavilion::testing::TestDir() / "text.png";
      WritePng(png.string(), image);
      const std::string bytes = pavilion::testing::ReadTextFile(png);
      ASSERT_GT(bytes.size(), 8u);
      EXPECT_EQ(bytes.substr(1, 3), "PNG");
    }
  }
}

// Every printable ASCII character has its own glyph, inside 5 columns, with
// ink except the space; only g, j, p, q, y reach below the baseline; other
// bytes draw '?'; a UTF-8 sequence is one glyph.
TEST(RasterTest, FontCoversPrintableAscii) {
  std::set<std::array<std::uint8_t, kGlyphHeightPx>> seen;
  for (char c = 0x20; c <= 0x7E; ++c) {
    const auto& rows = Glyph(c);
    int ink = 0;
    for (const std::uint8_t row : rows) {
      EXPECT_LT(row, 1 << kGlyphWidthPx) << c;
      ink += row != 0;
    }
    EXPECT_EQ(ink > 0, c != ' ') << c;
    const bool descends = rows[kGlyphHeightPx - 2] != 0 || rows[kGlyphHeightPx - 1] != 0;
    EXPECT_EQ(descends, std::string("gjpqy").find(c) != std::string::npos) << c;
    EXPECT_TRUE(seen.insert(rows).second) << "glyph of '" << c << "' repeats another";
  }
  EXPECT_EQ(Glyph('\x01'), Glyph('?'));
  EXPECT_EQ(Glyph('\xC2'), Glyph('?'));
  EXPECT_EQ(MeasureText("5\xC2\xB0").width_px, kGlyphAdvancePx + kGlyphWidthPx);  // "5°"
  EXPECT_EQ(MeasureText("ab\n").height_px, kGlyphHeightPx);
  EXPECT_EQ(MeasureText("").width_px, 0);
}

// A one-pixel line along a pixel border (y = 5.0) is unbroken: every column
// between its ends has a pixel of it in row 4 or 5.
TEST(RasterTest, ThinLineAlongAPixelBorderIsUnbroken) {
  core::RgbImage image(40, 10);
  DrawLine(&image, Eigen::Vector2d(2.0, 5.0), Eigen::Vector2d(37.0, 5.0), 1.0, kInk);
  for (int x = 2; x < 37; ++x) {
    EXPECT_TRUE(IsInk(image, x, 4) || IsInk(image, x, 5)) << x;
  }
  int inside = 0, outside = 0;
  CountInk(image, 2, 4, 36, 2, &inside, &outside);
  EXPECT_EQ(outside, 0);
}

// Drawing across the border clips instead of writing outside the image.
TEST(RasterTest, PrimitivesClipAtTheBorder) {
  core::RgbImage image(20, 10);
  DrawText(&image, -7, -3, "Clipped text", 2, kInk);
  FillRect(&image, 15, 5, 100, 100, kInk);
  FillDisc(&image, Eigen::Vector2d(0.0, 0.0), 4.0, kInk);
  DrawLine(&image, Eigen::Vector2d(-50.0, 5.0), Eigen::Vector2d(70.0, 5.0), 3.0, kInk);
  DrawEllipse(&image, Eigen::Vector2d(10.0, 5.0), Eigen::Matrix2d::Identity() * 400.0, 5.99, kInk);
  EXPECT_EQ(image.pixels.size(), 20u * 10u * 3u);
  EXPECT_TRUE(IsInk(image, 19, 9));
  EXPECT_TRUE(IsInk(image, 0, 0));

  core::RgbImage small(3, 2, 1, 2, 3);
  core::RgbImage canvas(5, 5);
  Blit(small, 3, 4, &canvas);  // only (3, 4) and (4, 4) land inside
  int copied = 0;
  for (std::size_t i = 0; i < canvas.pixels.size(); i += 3) copied += canvas.pixels[i] == 1;
  EXPECT_EQ(copied, 2);
}

}  // namespace
}  // namespace pavilion::scenarios
