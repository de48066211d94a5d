#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/types/image.h"

namespace pavilion::scenarios {

// Encodes an RGB image as PNG bytes (libpng; no time stamp, so the bytes are
// reproducible).
std::vector<std::uint8_t> EncodePng(const core::RgbImage& image);

// Writes a PNG file atomically; throws std::runtime_error naming the file.
void WritePng(const std::string& path, const core::RgbImage& image);

// Standard base64 of bytes (for images embedded in report.html).
std::string Base64(const std::vector<std::uint8_t>& bytes);

}  // namespace pavilion::scenarios
