#include "rooms/room_score.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <unordered_map>
#include <vector>

namespace semvox {

RoomScore ScoreRooms(const ImageU16& predicted, const ImageU16& ground_truth) {
  RoomScore score;
  if (predicted.width != ground_truth.width || predicted.height != ground_truth.height) return score;
  const size_t n = predicted.data.size();
  std::unordered_map<int, int64_t> pred_area, gt_area;
  std::unordered_map<int64_t, int64_t> overlap;  // (gt << 16 | pred) -> pixels.
  for (size_t i = 0; i < n; ++i) {
    const int p = predicted.data[i], g = ground_truth.data[i];
    if (p) ++pred_area[p];
    if (g) ++gt_area[g];
    if (p && g) ++overlap[(int64_t(g) << 16) | p];
  }
  std::unordered_map<int, int64_t> best_for_gt, best_for_pred;
  for (const auto& [key, count] : overlap) {
    const int g = int(key >> 16), p = int(key & 0xffff);
    best_for_gt[g] = std::max(best_for_gt[g], count);
    best_for_pred[p] = std::max(best_for_pred[p], count);
  }
  double r = 0, pr = 0;
  for (const auto& [g, area] : gt_area) r += double(best_for_gt[g]) / double(area);
  for (const auto& [p, area] : pred_area) pr += double(best_for_pred[p]) / double(area);
  score.num_ground_truth_rooms = int(gt_area.size());
  score.num_predicted_rooms = int(pred_area.size());
  score.recall = gt_area.empty() ? 0 : r / double(gt_area.size());
  score.precision = pred_area.empty() ? 0 : pr / double(pred_area.size());
  return score;
}

ImageU16 GroundTruthRoomsFromImage(const Image<uint8_t>& grey, int free_threshold, int min_room_px) {
  const int W = grey.width, H = grey.height;
  ImageU16 out(W, H, 1, 0);
  if (W == 0 || H == 0) return out;
  cv::Mat1b mask(H, W, uchar(0));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) mask(y, x) = grey.at(x, y) > free_threshold ? 255 : 0;
  cv::Mat1i labels;
  cv::Mat stats, centroids;
  const int k = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  std::vector<int> id(k, 0);
  int next = 0;
  for (int c = 1; c < k; ++c)
    if (stats.at<int>(c, cv::CC_STAT_AREA) >= min_room_px && next < 65535) id[c] = ++next;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) out.at(x, y) = uint16_t(id[labels(y, x)]);
  return out;
}

}  // namespace semvox
