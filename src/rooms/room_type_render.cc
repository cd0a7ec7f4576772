// Room-type CRF: accuracy against ground truth and the coloured type map (room_type_crf.h).
#include "rooms/room_type_crf.h"

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>
#include <unordered_map>

#include "core/file_util.h"
#include "core/labels.h"
#include "rooms/room_type_crf_internal.h"

namespace semvox {

using namespace room_type_internal;

void RoomTypeAccuracy::Add(const ImageU16& predicted, const ImageU16& truth) {
  for (size_t i = 0; i < truth.data.size() && i < predicted.data.size(); ++i) {
    const int t = truth.data[i];
    if (t < 1 || t > kRoomTypeLabels) continue;
    total[size_t(t)] += 1;
    correct[size_t(t)] += predicted.data[i] == t;
  }
}

double RoomTypeAccuracy::Global() const {
  const double n = std::accumulate(total.begin(), total.end(), 0.0);
  return n > 0 ? std::accumulate(correct.begin(), correct.end(), 0.0) / n : 0.0;
}

double RoomTypeAccuracy::Average() const {
  double sum = 0;
  int types = 0;
  for (size_t t = 1; t < total.size(); ++t)
    if (total[t] > 0) sum += correct[t] / total[t], ++types;
  return types > 0 ? sum / types : 0.0;
}

ImageRgb8 RenderRoomTypes(const FloorPlan& plan, const ImageU16& pixel_types) {
  // One colour per room type id 1..12 (index 0: room space without a type).
  static const uint8_t kColours[kRoomTypeLabels + 1][3] = {
      {200, 200, 200}, {66, 146, 198}, {116, 196, 118}, {253, 174, 107}, {189, 189, 189}, {203, 24, 29},  {255, 217, 47},
      {158, 154, 200}, {231, 41, 138}, {102, 194, 165}, {140, 81, 10},   {191, 129, 45},  {90, 90, 90}};
  const int W = plan.width(), H = plan.height();
  ImageRgb8 img(W, H, 3, 255);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const FloorCell c = plan.at(x, y);
      const int t = pixel_types.empty() ? 0 : pixel_types.at(x, y);
      uint8_t rgb[3] = {255, 255, 255};
      if (c == FloorCell::kWall) rgb[0] = rgb[1] = rgb[2] = 32;
      else if (t >= 1 && t <= kRoomTypeLabels) {
        const double shade = c == FloorCell::kClutter ? 0.7 : 1.0;
        for (int k = 0; k < 3; ++k) rgb[k] = uint8_t(kColours[t][k] * shade);
      } else if (c == FloorCell::kFree || c == FloorCell::kDoor || c == FloorCell::kClutter) {
        for (int k = 0; k < 3; ++k) rgb[k] = kColours[0][k];
      }
      for (int k = 0; k < 3; ++k) img.at(x, y, k) = rgb[k];
    }
  return img;
}

}  // namespace semvox
