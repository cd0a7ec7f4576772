// Image files (PNG, JPEG, ...) through OpenCV, in core image types. Writes are atomic.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/geometry.h"
#include "core/image.h"
#include "core/status.h"

namespace semvox {

Result<ImageRgb8> ReadImageRgb8(const std::string& path);
Result<ImageRgb8> DecodeImageRgb8(const std::string& bytes, const std::string& name);
// Single-channel 8-bit image (colour is converted to grey, 16-bit is scaled down): 2D maps.
Result<Image<uint8_t>> ReadImageGrey8(const std::string& path);
// 8-bit grey or 16-bit single-channel image, as stored (no scaling).
Result<ImageU16> ReadImageU16(const std::string& path);

// Encodes by extension (.png, .pgm, .jpg) and writes atomically.
Status WriteImage(const std::string& path, const ImageRgb8& image);  // 3 channels RGB, or 1 channel grey.
Status WriteImage(const std::string& path, const ImageU16& image);   // 16-bit PNG.

// `image` (RGB) with a legend to its right: one colour swatch and name per entry, on white.
ImageRgb8 AppendLegend(const ImageRgb8& image, const std::vector<std::pair<Rgb8, std::string>>& entries);

}  // namespace semvox
