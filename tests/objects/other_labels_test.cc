// Fine labels of the "other" class (objects/other_labels.h): the features on a hand-built room, the ids
// "other" covers, the model file, and a labeller trained on generated scans against held-out scans.
#include "objects/other_labels.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "core/labels.h"
#include "objects/segment_training.h"
#include "perception/knn_unary.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

constexpr double kRes = 0.05;

// A 4 x 4 m room at 5 cm (floor layer at cell 0, walls 2.5 m high) with a bed (2.0 x 1.5 m, 0.5 m high,
// solid) and a cushion (0.3 x 0.3 m, 0.15 m high) on it: too small a footprint to be a part of its own,
// so it stays in the bed's segment.
struct BedRoom {
  VoxelGrid grid{kRes, {32768 - 10, 32768 - 10, 32768}, {100, 100, 56}};
  static int C(double m) { return int(std::floor(m / kRes + 1e-9)); }
  std::vector<uint32_t> Fill(double x0, double y0, double z0, double x1, double y1, double z1) {
    std::vector<uint32_t> cells;
    for (int z = C(z0); z < C(z1); ++z)
      for (int y = 10 + C(y0); y < 10 + C(y1); ++y)
        for (int x = 10 + C(x0); x < 10 + C(x1); ++x) {
          grid.set_state(grid.Index(x, y, z), VoxelState::kOccupied);
          cells.push_back(uint32_t(grid.Index(x, y, z)));
        }
    std::sort(cells.begin(), cells.end());
    return cells;
  }
  std::vector<uint32_t> cushion;
  BedRoom() {
    Fill(0, 0, 0, 4, 4, 0.05);
    Fill(-0.05, -0.05, 0, 0, 4.05, 2.5);
    Fill(4, -0.05, 0, 4.05, 4.05, 2.5);
    Fill(0, -0.05, 0, 4, 0, 2.5);
    Fill(0, 4, 0, 4, 4.05, 2.5);
    Fill(1.0, 1.0, 0.05, 3.0, 2.5, 0.5);
    cushion = Fill(1.5, 1.5, 0.5, 1.8, 1.8, 0.65);
  }
  double FloorZ() const { return grid.CellCenter(0, 0, 0).z(); }
};

TEST(OtherLabels, FeaturesDescribeTheOtherVoxelsAndWhatHoldsThem) {
  BedRoom room;
  const double floor_z = room.FloorZ();
  const SegmentationResult seg = SegmentObjects(room.grid, floor_z, floor_z + 2.5, false, SegmentOptions{});
  ASSERT_EQ(seg.segments.size(), 1u);
  const ObjectSegment& bed = seg.segments[0];
  ASSERT_TRUE(std::includes(bed.voxels.begin(), bed.voxels.end(), room.cushion.begin(), room.cushion.end()));
  // The whole segment described again gives its own features (the rise is SegmentObjects' alone).
  const std::array<float, kNumSegmentFeatures> whole = DescribeVoxels(room.grid, bed.voxels, seg);
  for (int f = 0; f < kNumSegmentFeatures; ++f) {
    if (f == kSegNeighbourRise) continue;
    EXPECT_FLOAT_EQ(whole[size_t(f)], bed.features[size_t(f)]) << SegmentFeatureName(f);
  }
  // The cushion alone: its own size and height, on a 2 x 1.5 m support whose top surface is the bed's.
  const OtherFeatureVector f = OtherFeatures(room.grid, seg, bed, room.cushion);
  const double tol = 0.051;
  EXPECT_NEAR(f[kSegLength], 0.3, tol);
  EXPECT_NEAR(f[kSegWidth], 0.3, tol);
  EXPECT_NEAR(f[kSegBottom], 0.5, tol);  // lowest voxel centre 0.525 m, the floor's 0.025 m
  EXPECT_NEAR(f[kSegTop], 0.6, tol);
  EXPECT_FLOAT_EQ(f[kSegNeighbourRise], 0.0f);  // nothing of the segment rises above it
  EXPECT_NEAR(f[kOtherShare], double(room.cushion.size()) / double(bed.voxels.size()), 1e-6);
  EXPECT_NEAR(f[kOtherSupportTop], 0.45, tol);  // the bed's top surface
  EXPECT_NEAR(f[kOtherSegmentFootprint], 3.0, 0.2);
  // The bed's body alone (what a cushion sits on) lies under the segment's top by the cushion's height.
  std::vector<uint32_t> body;
  std::set_difference(bed.voxels.begin(), bed.voxels.end(), room.cushion.begin(), room.cushion.end(), std::back_inserter(body));
  EXPECT_NEAR(OtherFeatures(room.grid, seg, bed, body)[kSegNeighbourRise], 0.15, tol);
  // The cushion is the one item on top of the bed (its voxels above the mattress's top layer); a larger
  // least size leaves none.
  const std::vector<std::vector<uint32_t>> items = ItemsOnTop(room.grid, seg, bed, kOtherMinVoxels);
  ASSERT_EQ(items.size(), 1u);
  EXPECT_EQ(items[0], room.cushion);
  EXPECT_TRUE(ItemsOnTop(room.grid, seg, bed, int(room.cushion.size()) + 1).empty());
}

TEST(OtherLabels, ItemsOnTopAreSeparateGroupsAndTheItemLabellerVotesPlainly) {
  BedRoom room;
  const std::vector<uint32_t> second = room.Fill(2.4, 1.5, 0.5, 2.7, 1.8, 0.6);  // a book, apart from the cushion
  const double floor_z = room.FloorZ();
  const SegmentationResult seg = SegmentObjects(room.grid, floor_z, floor_z + 2.5, false, SegmentOptions{});
  ASSERT_EQ(seg.segments.size(), 1u);
  const std::vector<std::vector<uint32_t>> items = ItemsOnTop(room.grid, seg, seg.segments[0], kOtherMinVoxels);
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0], room.cushion);
  EXPECT_EQ(items[1], second);
  // Plain majority of the k nearest (no class-frequency normalisation): 2 of 3 neighbours say "part of the
  // furniture" (0), though class 0 has three times the rows of the pillow (with Eq. 4 the pillow would win).
  std::vector<float> x;
  std::vector<int> y;
  for (int r = 0; r < 8; ++r) {
    std::vector<float> row(kNumOtherFeatures, 0.f);
    row[0] = r < 6 ? 0.f : 0.1f;
    if (r >= 2 && r < 6) row[0] = 5.f;  // far rows of class 0
    x.insert(x.end(), row.begin(), row.end());
    y.push_back(r < 6 ? 0 : nyu40::kPillow);
  }
  KnnOptions o;
  o.k = 3;
  o.standardise = false;
  const ItemLabeller labeller(KnnClassifier::Train(x, kNumOtherFeatures, y, kNumNyu40, o).value());
  std::vector<float> q(kNumOtherFeatures, 0.f);
  q[0] = 0.04f;  // nearest: two class-0 rows at 0, one pillow row at 0.1
  EXPECT_EQ(labeller.Label(q), 0);
  q[0] = 0.1f;  // nearest: two pillow rows
  EXPECT_EQ(labeller.Label(q), nyu40::kPillow);
  // Far from every training group (nearest 2.4 m away in this feature, the training groups' own neighbours
  // within 0.07): unfamiliar, so part of the furniture whatever its neighbours say.
  q[0] = 2.5f;
  EXPECT_EQ(labeller.Label(q), 0);
  q[1] = 3.0f;
  q[0] = 0.1f;
  EXPECT_EQ(labeller.Label(q), 0);
}

TEST(OtherLabels, OtherCoversTheNyu40IdsOutsideScanNet20AndCeiling) {
  for (int id : {nyu40::kPillow, nyu40::kBox, nyu40::kLamp, nyu40::kTelevision, nyu40::kNightStand, nyu40::kDresser, nyu40::kBooks,
                 nyu40::kOtherProp, nyu40::kShelves})
    EXPECT_TRUE(IsOtherNyu40(id)) << id;
  for (int id : {0, nyu40::kWall, nyu40::kFloor, nyu40::kBed, nyu40::kPicture, nyu40::kCeiling, nyu40::kOtherFurniture, -1, kNumNyu40})
    EXPECT_FALSE(IsOtherNyu40(id)) << id;
}

TEST(OtherLabels, TheLabelIsAnOtherIdAndABadFileIsAnErrorNamingIt) {
  // Two rows: a "table" row (not an "other" id) nearest to the query still gives an "other" id.
  std::vector<float> x(2 * kNumOtherFeatures, 0.f);
  x[kNumOtherFeatures] = 1.f;
  KnnOptions o;
  o.k = 1;
  const OtherLabeller fine(KnnClassifier::Train(x, kNumOtherFeatures, {nyu40::kTable, nyu40::kLamp}, kNumNyu40, o).value());
  std::vector<float> q(kNumOtherFeatures, 0.f);
  EXPECT_TRUE(IsOtherNyu40(fine.Label(q)));
  q[0] = 1.f;
  EXPECT_EQ(fine.Label(q), nyu40::kLamp);
  testing::ScratchDir dir("other_labels");
  ASSERT_TRUE(fine.Save(dir.File(kOtherLabellerFile)).ok());
  Result<OtherLabeller> back = OtherLabeller::Load(dir.File(kOtherLabellerFile));
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_EQ(back->Label(q), nyu40::kLamp);
  // A k-NN of other dimensions (a segment classifier) is refused with the file's name.
  ASSERT_TRUE(KnnClassifier::Train({0.f, 1.f}, 1, {0, 1}, 2, o)->Save(dir.File("wrong.knn")).ok());
  Result<OtherLabeller> wrong = OtherLabeller::Load(dir.File("wrong.knn"));
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.status().message().find("wrong.knn"), std::string::npos);
  EXPECT_FALSE(OtherLabeller::Load(dir.File("absent.knn")).ok());
}

// Trained on the randomised scans of a dozen generated apartments, the labeller names the "other" objects
// of three held-out ones far better than the one id everything "other" had before.
TEST(OtherLabels, TrainedOnGeneratedScansItNamesHeldOutObjects) {
  SegmentTrainingOptions o;
  for (uint64_t s = 0; s < 12; ++s) o.train_seeds.push_back(s);
  o.val_seeds = {100, 101, 102};
  SegmentTrainingSummary summary;
  std::optional<OtherLabeller> fine;
  std::optional<ItemLabeller> items;
  Result<SegmentClassifier> seg = TrainSegmentClassifier(o, &summary, &fine, &items);
  ASSERT_TRUE(seg.ok()) << seg.status().message();
  ASSERT_TRUE(fine.has_value() && items.has_value());
  EXPECT_GT(summary.other_train_rows, 100);
  ASSERT_GT(summary.other_val_rows, 20);
  // The best single id for every held-out "other" voxel.
  const ConfusionMatrix& m = summary.other_val_voxels;
  int64_t best_single = 0;
  for (int id = 0; id < m.m; ++id) {
    int64_t n = 0;
    for (int p = 0; p < m.m; ++p) n += m.counts[size_t(id) * size_t(m.m) + size_t(p)];
    best_single = std::max(best_single, n);
  }
  const double single = double(best_single) / double(m.Total());
  std::printf("other labels on seeds 100-102: %d rows, voxels right %.3f (one id for all: %.3f), class average %.3f\n",
              summary.other_val_rows, m.GlobalAccuracy(), single, m.AverageRecall());
  EXPECT_GT(m.GlobalAccuracy(), 0.44);  // measured 0.541 (one id for all: 0.207)
  EXPECT_GT(m.GlobalAccuracy(), single + 0.2) << "one id for all: " << single;
  EXPECT_GT(m.AverageRecall(), 0.45);  // measured 0.582
  // Items on top: most groups that are parts of their furniture stay so, and most voxels given an id of their
  // own are that object.
  ASSERT_GT(summary.item_val_rows, 20);
  const ConfusionMatrix& it = summary.item_val_voxels;
  int64_t called = 0, called_right = 0;
  for (int t = 0; t < it.m; ++t)
    for (int p = 1; p < it.m; ++p) called += it.counts[size_t(t) * size_t(it.m) + size_t(p)], called_right += t == p ? it.counts[size_t(t) * size_t(it.m) + size_t(p)] : 0;
  ASSERT_GT(called, 0);
  std::printf("items on top on seeds 100-102: %d groups, part of the furniture kept %.3f, precision of the ids given %.3f\n",
              summary.item_val_rows, it.Recall(0), double(called_right) / double(called));
  EXPECT_GT(it.Recall(0), 0.8);  // measured 0.992
  // Measured 0.573 when written, 0.444 since the varied toilets (2026-12-06). Twelve training apartments and 45
  // held-out groups: any change to the training scans moves it by a few points (0.43 with the tall cabinets tried
  // the day before); the full model's item labeller (seeds 0-99) keeps 0.68-0.76 of the item voxels right.
  EXPECT_GT(double(called_right) / double(called), 0.40);
}

}  // namespace
}  // namespace semvox
