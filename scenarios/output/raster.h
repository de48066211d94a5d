#pragma once

// Drawing primitives on an RgbImage for the command line's pictures, and a
// bitmap font (5 x 7 with descenders) for captions. Pixel coordinates: x to
// the right, y down; pixel (x, y) covers [x, x + 1) x [y, y + 1), so its centre
// is (x + 0.5, y + 0.5). Everything clips at the image border: drawing outside
// is a no-op.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string_view>

#include "core/types/image.h"

namespace pavilion::scenarios {

using Rgb = std::array<std::uint8_t, 3>;

void SetPixel(core::RgbImage* image, int x, int y, const Rgb& color);

// The pixels x in [x0, x0 + width_px), y in [y0, y0 + height_px).
void FillRect(core::RgbImage* image, int x0, int y0, int width_px, int height_px, const Rgb& color);

// The same rectangle blended: each pixel becomes alpha * color + (1 - alpha)
// * pixel, alpha in [0, 1] (clamped).
void BlendRect(core::RgbImage* image, int x0, int y0, int width_px, int height_px, const Rgb& color,
               double alpha);

// Pixels whose centre lies within radius_px of center_px.
void FillDisc(core::RgbImage* image, const Eigen::Vector2d& center_px, double radius_px,
              const Rgb& color);

// A line width_px wide, stamped as discs every half pixel; width_px <= 1 gives
// a connected line of single pixels.
void DrawLine(core::RgbImage* image, const Eigen::Vector2d& a_px, const Eigen::Vector2d& b_px,
              double width_px, const Rgb& color);

// Outline of {p : (p - c)^T covariance^-1 (p - c) = chi2} as a polygon of
// `vertices` sides, covariance in pixels^2; semi-axes of at least 1 px, so a
// tiny ellipse stays visible.
void DrawEllipse(core::RgbImage* image, const Eigen::Vector2d& center_px,
                 const Eigen::Matrix2d& covariance_px2, double chi2, const Rgb& color,
                 int vertices = 96);

// Copies `source` into `image` with its top-left pixel at (x0, y0).
void Blit(const core::RgbImage& source, int x0, int y0, core::RgbImage* image);

// --- Text -------------------------------------------------------------------

// Font metrics at scale 1: a glyph cell is 5 x 9 pixels. Capitals, digits and
// ascenders fill rows 0 to 6 (row 6 is the baseline row), lower case letters
// rows 2 to 6, and the descenders of g, j, p, q, y rows 7 and 8. Glyphs advance
// by 6 pixels and lines by 11.
inline constexpr int kGlyphWidthPx = 5;
inline constexpr int kGlyphHeightPx = 9;
inline constexpr int kGlyphAdvancePx = 6;
inline constexpr int kLineAdvancePx = 11;

// The rows of the glyph of `c`, top to bottom; bit 4 of a row is its leftmost
// pixel. Printable ASCII (0x20 to 0x7E) has glyphs; any other byte gets '?'.
const std::array<std::uint8_t, kGlyphHeightPx>& Glyph(char c);

struct TextExtent {
  int width_px = 0;   // the widest line
  int height_px = 0;  // from the top of the first line to the bottom of the last
};

// Size of `text` drawn by DrawText at `scale` (>= 1). Lines end at '\n' (a
// final '\n' adds no line); a UTF-8 sequence of several bytes is one glyph
// ('?'), a tab one space. Empty text: 0 x 0.
TextExtent MeasureText(std::string_view text, int scale = 1);

// Draws `text` with the top-left corner of its first glyph at (x_px, y_px),
// each font pixel as a scale x scale square (scale >= 1; less is taken as 1).
// Every pixel set lies inside the MeasureText box at (x_px, y_px).
void DrawText(core::RgbImage* image, int x_px, int y_px, std::string_view text, int scale,
              const Rgb& color);

}  // namespace pavilion::scenarios
