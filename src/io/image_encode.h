// In-memory image encoding (PNG through OpenCV), for outputs that embed images (report.html).
#pragma once

#include <string>

#include "core/image.h"
#include "core/status.h"

namespace semvox {

// PNG bytes of `image`: 3 channels RGB or 1 channel grey, 8 bits.
Result<std::string> EncodePng(const ImageRgb8& image);

}  // namespace semvox
