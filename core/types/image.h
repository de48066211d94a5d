#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pavilion::core {

// An 8-bit RGB image, rows top to bottom, 3 bytes per pixel.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // width * height * 3

  RgbImage() = default;
  RgbImage(int w, int h, std::uint8_t r = 255, std::uint8_t g = 255, std::uint8_t b = 255)
      : width(w), height(h), pixels(static_cast<std::size_t>(w) * h * 3) {
    for (std::size_t i = 0; i < pixels.size(); i += 3) {
      pixels[i] = r;
      pixels[i + 1] = g;
      pixels[i + 2] = b;
    }
  }
};

// An 8-bit grey-level image (the Pulnix TM-9701's, §2.4), rows top to bottom,
// one byte per pixel. Pixel (u, v) covers [u, u + 1) x [v, v + 1) in image
// coordinates: its centre is (u + 0.5, v + 0.5).
struct GrayImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // width * height, row-major

  GrayImage() = default;
  GrayImage(int w, int h, std::uint8_t value = 0)
      : width(w), height(h), pixels(static_cast<std::size_t>(w) * h, value) {}

  std::uint8_t at(int u, int v) const { return pixels[static_cast<std::size_t>(v) * width + u]; }
  std::uint8_t& at(int u, int v) { return pixels[static_cast<std::size_t>(v) * width + u]; }
};

}  // namespace pavilion::core
