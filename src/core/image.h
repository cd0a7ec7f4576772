// Plain images: row-major, row 0 at the top, interleaved channels.
#pragma once

#include <cstdint>
#include <vector>

namespace semvox {

template <typename T>
struct Image {
  int width = 0;
  int height = 0;
  int channels = 1;
  std::vector<T> data;  // width * height * channels values.

  Image() = default;
  Image(int w, int h, int c, T fill = T()) : width(w), height(h), channels(c), data(size_t(w) * h * c, fill) {}
  bool empty() const { return data.empty(); }
  T& at(int x, int y, int c = 0) { return data[(size_t(y) * width + x) * channels + c]; }
  const T& at(int x, int y, int c = 0) const { return data[(size_t(y) * width + x) * channels + c]; }
};

using ImageRgb8 = Image<uint8_t>;   // channels = 3 (R, G, B).
using ImageU16 = Image<uint16_t>;   // channels = 1.
using ImageF32 = Image<float>;

}  // namespace semvox
