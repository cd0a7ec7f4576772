#include "rooms/room_score.h"

#include <gtest/gtest.h>

namespace semvox {
namespace {

ImageU16 Stripes(int w, int h, std::initializer_list<int> widths) {
  ImageU16 img(w, h, 1, 0);
  int x0 = 0, id = 1;
  for (int sw : widths) {
    for (int y = 0; y < h; ++y)
      for (int x = x0; x < x0 + sw && x < w; ++x) img.at(x, y) = uint16_t(id);
    x0 += sw, ++id;
  }
  return img;
}

TEST(ScoreRooms, IdenticalSegmentationsScoreOne) {
  const ImageU16 a = Stripes(40, 10, {10, 20, 10});
  const RoomScore s = ScoreRooms(a, a);
  EXPECT_DOUBLE_EQ(s.recall, 1.0);
  EXPECT_DOUBLE_EQ(s.precision, 1.0);
  EXPECT_EQ(s.num_ground_truth_rooms, 3);
}

// Bormann et al. 2016: merging two equal rooms halves precision of the merged room; splitting a room
// in two halves its recall.
TEST(ScoreRooms, MergesCostPrecisionSplitsCostRecall) {
  const ImageU16 gt = Stripes(40, 10, {20, 20});
  const ImageU16 merged = Stripes(40, 10, {40});
  RoomScore s = ScoreRooms(merged, gt);
  EXPECT_DOUBLE_EQ(s.recall, 1.0);
  EXPECT_DOUBLE_EQ(s.precision, 0.5);
  const ImageU16 split = Stripes(40, 10, {10, 10, 20});
  s = ScoreRooms(split, gt);
  EXPECT_DOUBLE_EQ(s.recall, 0.75);
  EXPECT_DOUBLE_EQ(s.precision, 1.0);
}

TEST(ScoreRooms, PredictedCellsOutsideEveryRoomCountAgainstPrecision) {
  ImageU16 gt = Stripes(40, 10, {20});
  const ImageU16 pred = Stripes(40, 10, {40});
  const RoomScore s = ScoreRooms(pred, gt);
  EXPECT_DOUBLE_EQ(s.recall, 1.0);
  EXPECT_DOUBLE_EQ(s.precision, 0.5);
}

TEST(GroundTruthRoomsFromImage, ThresholdsAndDropsSmallComponents) {
  Image<uint8_t> grey(30, 10, 1, 0);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 12; ++x) grey.at(x, y) = 255;  // 120 px: a room.
  for (int y = 0; y < 10; ++y)
    for (int x = 14; x < 24; ++x) grey.at(x, y) = 255;  // 100 px: dropped (<= 100).
  for (int y = 0; y < 10; ++y) grey.at(27, y) = 250;    // Not brighter than 250.
  const ImageU16 gt = GroundTruthRoomsFromImage(grey);
  EXPECT_EQ(gt.at(0, 0), 1);
  EXPECT_EQ(gt.at(15, 5), 0);
  EXPECT_EQ(gt.at(27, 5), 0);
}

}  // namespace
}  // namespace semvox
