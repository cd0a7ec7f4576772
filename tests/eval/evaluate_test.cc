// semvox eval on hand-built cases: a perfect prediction scores 100 %, known mistakes give exact figures,
// missing prediction files are reported absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/labels.h"
#include "core/ply.h"
#include "core/voxel_key.h"
#include "eval/evaluate.h"
#include "io/image_io.h"
#include "mapping/occupancy_map.h"
#include "scenegen/apartment.h"
#include "scenegen/apartment_io.h"
#include "scenegen/mesh_builder.h"

namespace semvox {
namespace {

namespace fs = std::filesystem;
using namespace nyu40;

uint64_t Key(int x, int y, int z) { return VoxelKey{uint16_t(kKeyOffset + x), uint16_t(kKeyOffset + y), uint16_t(kKeyOffset + z)}.Pack(); }

FloorGrid Grid(int w, int h, double res = 0.1) {
  FloorGrid g;
  g.resolution = res;
  g.width = w;
  g.height = h;
  return g;
}

TEST(ScoreVoxels, KnownMistakeGivesExactFigures) {
  const VoxelLabels gt = {{Key(0, 0, 0), kWall}, {Key(1, 0, 0), kWall}, {Key(2, 0, 0), kFloor}, {Key(3, 0, 0), kChair},
                          {Key(9, 9, 9), kBed}};  // Not in the prediction: not visible.
  const VoxelLabels pred = {{Key(0, 0, 0), kWall}, {Key(1, 0, 0), kFloor}, {Key(2, 0, 0), kFloor}, {Key(3, 0, 0), kChair},
                            {Key(5, 5, 5), kTable}};  // Not in the ground truth: ignored.
  const VoxelScores s = ScoreVoxels(gt, pred);
  EXPECT_EQ(s.visible, 4u);
  EXPECT_EQ(s.gt_voxels, 5u);
  EXPECT_DOUBLE_EQ(s.accuracy.value, 3.0 / 4);
  EXPECT_DOUBLE_EQ(s.mean_recall.value, (0.5 + 1 + 1) / 3);
  // IoU: wall 1/(2+1-1), floor 1/(1+2-1), chair 1.
  EXPECT_DOUBLE_EQ(s.mean_iou.value, (0.5 + 0.5 + 1) / 3);
  EXPECT_DOUBLE_EQ(s.iou_per_class.at(kWall), 0.5);
  // NYU-4: wall -> structure, floor -> ground, chair -> furniture; one structure voxel called ground.
  EXPECT_DOUBLE_EQ(s.nyu4_recall[0].value, 1.0);
  EXPECT_DOUBLE_EQ(s.nyu4_recall[1].value, 0.5);
  EXPECT_DOUBLE_EQ(s.nyu4_recall[2].value, 1.0);
  EXPECT_FALSE(s.nyu4_recall[3].present) << "no props in the ground truth";
  EXPECT_DOUBLE_EQ(s.nyu4_average.value, 2.5 / 3);
  EXPECT_DOUBLE_EQ(s.nyu4_global.value, 3.0 / 4);
  // Per class: the wall's one mistake went to floor; floor and chair were all right.
  ASSERT_EQ(s.per_class.size(), 3u);
  EXPECT_EQ(s.per_class.at(kWall).count, 2u);
  EXPECT_EQ(s.per_class.at(kWall).correct, 1u);
  EXPECT_EQ(s.per_class.at(kWall).most_confused_with, kFloor);
  ASSERT_EQ(s.per_class.at(kWall).confusions.size(), 1u);
  EXPECT_EQ(s.per_class.at(kWall).confusions[0], (std::pair<int, size_t>(kFloor, 1)));
  EXPECT_EQ(s.per_class.at(kFloor).most_confused_with, -1);
  EXPECT_TRUE(s.per_class.at(kChair).confusions.empty());
}

TEST(ScoreVoxels, PerfectPredictionIsHundredPercent) {
  const VoxelLabels gt = {{Key(0, 0, 0), kWall}, {Key(1, 0, 0), kFloor}, {Key(2, 0, 0), kBooks}};
  const VoxelScores s = ScoreVoxels(gt, gt);
  EXPECT_DOUBLE_EQ(s.accuracy.value, 1.0);
  EXPECT_DOUBLE_EQ(s.mean_iou.value, 1.0);
  EXPECT_DOUBLE_EQ(s.nyu4_average.value, 1.0);
  EXPECT_DOUBLE_EQ(s.nyu4_global.value, 1.0);
}

TEST(ScoreRoomSegmentation, MergedAndSplitRoomsGiveExactFigures) {
  // Ground truth: room 1 = left 10x10 pixels, room 2 = right 10x10 pixels.
  const FloorGrid g = Grid(20, 10);
  ImageU16 gt(20, 10, 1, 0);
  for (int r = 0; r < 10; ++r)
    for (int c = 0; c < 20; ++c) gt.at(c, r) = c < 10 ? 1 : 2;
  // One predicted room over both: recall 1, precision 1/2.
  ImageU16 merged(20, 10, 1, 7);
  RoomSegmentationScores s = ScoreRoomSegmentation(gt, g, merged, g);
  EXPECT_DOUBLE_EQ(s.recall.value, 1.0);
  EXPECT_DOUBLE_EQ(s.precision.value, 0.5);
  // Room 1 split into halves, room 2 right: recall (1/2 + 1)/2, precision 1.
  ImageU16 split = gt;
  for (int r = 0; r < 10; ++r)
    for (int c = 0; c < 10; ++c) split.at(c, r) = r < 5 ? 3 : 4;
  s = ScoreRoomSegmentation(gt, g, split, g);
  EXPECT_DOUBLE_EQ(s.recall.value, 0.75);
  EXPECT_DOUBLE_EQ(s.precision.value, 1.0);
  EXPECT_EQ(s.predicted_rooms, 3);
  // Perfect, and on a prediction grid of a different resolution and origin.
  FloorGrid fine = Grid(44, 24, 0.05);
  fine.origin_x = -0.1;
  fine.origin_y = -0.1;
  ImageU16 pred(44, 24, 1, 0);
  for (int r = 0; r < 24; ++r)
    for (int c = 0; c < 44; ++c) {
      const double x = fine.CenterX(c), y = fine.CenterY(r);
      if (x > 0 && x < 2 && y > 0 && y < 1) pred.at(c, r) = x < 1 ? 5 : 6;
    }
  s = ScoreRoomSegmentation(gt, g, pred, fine);
  EXPECT_NEAR(s.recall.value, 1.0, 1e-12);  // Sums of pixel areas in floating point.
  EXPECT_NEAR(s.precision.value, 1.0, 1e-12);
}

TEST(ScoreRoomTypes, KnownMistakeGivesExactFigures) {
  // Room 1 (bedroom) 10x10 pixels, room 2 (kitchen) 5x10 pixels; both predicted bedroom.
  const FloorGrid g = Grid(15, 10);
  ImageU16 gt(15, 10, 1, 0);
  for (int r = 0; r < 10; ++r)
    for (int c = 0; c < 15; ++c) gt.at(c, r) = c < 10 ? 1 : 2;
  const int bedroom = RoomTypeIdByName("bedroom"), kitchen = RoomTypeIdByName("kitchen");
  const std::map<int, int> gt_types = {{1, bedroom}, {2, kitchen}};
  RoomTypeScores s = ScoreRoomTypes(gt, g, gt_types, gt, g, {{1, bedroom}, {2, bedroom}});
  EXPECT_DOUBLE_EQ(s.global.value, 100.0 / 150);
  EXPECT_DOUBLE_EQ(s.average.value, 0.5);
  s = ScoreRoomTypes(gt, g, gt_types, gt, g, gt_types);
  EXPECT_DOUBLE_EQ(s.global.value, 1.0);
  EXPECT_DOUBLE_EQ(s.average.value, 1.0);
  // A room the prediction leaves untyped (not in rooms.geojson) counts as unknown.
  s = ScoreRoomTypes(gt, g, gt_types, gt, g, {{1, bedroom}});
  EXPECT_DOUBLE_EQ(s.global.value, 100.0 / 150);
  EXPECT_EQ(s.confusion_pixels[kitchen][0], 50u);
  EXPECT_EQ(s.confusion_pixels[bedroom][bedroom], 100u);
  // A ground-truth room without a type (a real plan's entrance) is not scored, whatever is predicted there.
  s = ScoreRoomTypes(gt, g, {{1, bedroom}, {2, 0}}, gt, g, {{1, bedroom}, {2, kitchen}});
  EXPECT_DOUBLE_EQ(s.global.value, 1.0);
  EXPECT_DOUBLE_EQ(s.average.value, 1.0);
  EXPECT_EQ(s.confusion_pixels.count(0), 0u);
}

TEST(ScoreTopView, KnownMistakeGivesExactFigures) {
  // 4x2 footprint: top row wall, wall, empty, table; bottom row empty (room 1).
  const FloorGrid g = Grid(4, 2);
  ImageU16 top(4, 2, 1, 0), rooms(4, 2, 1, 0);
  top.at(0, 0) = kWall, top.at(1, 0) = kWall, top.at(3, 0) = kTable;
  for (int c = 0; c < 4; ++c) rooms.at(c, 1) = 1;
  rooms.at(2, 0) = 1;
  OccupancyMap occ;
  occ.resolution = 0.1;
  occ.image = ImageRgb8(4, 2, 1, kPgmFree);
  occ.image.at(0, 0) = occ.image.at(1, 0) = occ.image.at(3, 0) = kPgmOccupied;
  ImageU16 pred = top;
  TopViewScores s = ScoreTopView(top, rooms, g, &occ, &pred);
  EXPECT_EQ(s.pixels, 8u);
  EXPECT_DOUBLE_EQ(s.geometric_accuracy.value, 1.0);
  EXPECT_DOUBLE_EQ(s.semantic_accuracy.value, 1.0);
  // Mistakes: the table column unknown (not occupied) and labelled chair; one empty cell labelled wall.
  occ.image.at(3, 0) = kPgmUnknown;
  pred.at(3, 0) = kChair;
  pred.at(0, 1) = kWall;
  s = ScoreTopView(top, rooms, g, &occ, &pred);
  EXPECT_DOUBLE_EQ(s.geometric_accuracy.value, 7.0 / 8);
  EXPECT_DOUBLE_EQ(s.predicted_unknown, 1.0 / 8);
  EXPECT_DOUBLE_EQ(s.semantic_global.value, 6.0 / 8);
  // Classes: empty 4/5, wall 2/2, table 0/1.
  EXPECT_DOUBLE_EQ(s.semantic_accuracy.value, (0.8 + 1 + 0) / 3);
  EXPECT_EQ(s.per_class.at(0).count, 5u);
  EXPECT_EQ(s.per_class.at(0).correct, 4u);
  EXPECT_EQ(s.per_class.at(0).most_confused_with, kWall);
  EXPECT_EQ(s.per_class.at(kTable).most_confused_with, kChair);
  EXPECT_EQ(s.per_class.at(kWall).most_confused_with, -1);
}

TEST(VoxelizeLabeledMesh, MajorityLabelPerVoxel) {
  MeshBuilder b;
  // A 0.2 m square at z = 0.025 (mid-voxel) labelled table: 4 x 4 voxels at 5 cm.
  b.AddQuad({0.001, 0.001, 0.025}, {0.199, 0.001, 0.025}, {0.199, 0.199, 0.025}, {0.001, 0.199, 0.025}, Rgb8{}, FaceTags{kTable, 0, 1});
  // Two small chair triangles and one book triangle inside voxel (0, 0, 2): chair wins.
  for (int k = 0; k < 2; ++k) b.AddTriangle({0.01, 0.01, 0.12}, {0.04, 0.01, 0.12}, {0.01, 0.04, 0.12}, Rgb8{}, FaceTags{kChair, 1, 1});
  b.AddTriangle({0.01, 0.01, 0.11}, {0.04, 0.01, 0.11}, {0.01, 0.04, 0.11}, Rgb8{}, FaceTags{kBooks, 2, 1});
  const VoxelLabels v = VoxelizeLabeledMesh(b.mesh(), 0.05);
  EXPECT_EQ(v.size(), 17u);
  EXPECT_EQ(v.at(Key(0, 0, 0)), kTable);
  EXPECT_EQ(v.at(Key(3, 3, 0)), kTable);
  EXPECT_EQ(v.at(Key(0, 0, 2)), kChair);
}

// End to end on a generated apartment: a prediction made from the ground truth itself scores 100 %.
class EvaluateEndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("semvox_eval_test_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    gt_ = root_ / "gt";
    pred_ = root_ / "pred";
    fs::create_directories(pred_);
    ApartmentOptions o;
    o.seed = 4;
    o.min_rooms = 3;
    o.max_rooms = 4;
    Result<Apartment> apt = GenerateApartment(o);
    ASSERT_TRUE(apt.ok());
    apt_ = std::move(apt).value();
    ScanArtefactOptions art;
    ASSERT_TRUE(WriteApartment(gt_.string(), apt_, o, art, GroundTruthOptions(), false).ok());
  }
  void TearDown() override { fs::remove_all(root_); }

  // Writes a perfect prediction; `damage` may alter it first.
  void WritePerfect() {
    const FloorGrid g = MakeFloorGrid(apt_, GroundTruthOptions());
    const ImageU16 top = RasterizeTopView(apt_, g, GroundTruthOptions()), rooms = RasterizeRooms(apt_, g);
    OccupancyMap occ;
    occ.resolution = g.resolution;
    occ.origin_x = g.origin_x;
    occ.origin_y = g.origin_y;
    occ.image = ImageRgb8(g.width, g.height, 1, kPgmFree);
    for (size_t i = 0; i < top.data.size(); ++i)
      if (top.data[i]) occ.image.data[i] = top.data[i] == kTopViewHidden ? kPgmUnknown : kPgmOccupied;
    ASSERT_TRUE(WriteOccupancyMap(occ, pred_.string(), "occupancy").ok());
    ASSERT_TRUE(WriteImage((pred_ / "rooms.png").string(), rooms).ok());
    std::ofstream geo(pred_ / "rooms.geojson");
    geo << R"({"type": "FeatureCollection", "features": [)";
    for (size_t i = 0; i < apt_.rooms.size(); ++i)
      geo << (i ? "," : "") << R"({"type": "Feature", "geometry": null, "properties": {"id": )" << apt_.rooms[i].id
          << R"(, "type_id": )" << apt_.rooms[i].type_id << "}}";
    geo << "]}";
    geo.close();
    // voxels.ply: the ground-truth surface voxels with their labels, plus, for the top view, the solid
    // interiors are not needed: the top view is scored against the highest labelled voxel.
    const VoxelLabels v = VoxelizeLabeledMesh(apt_.mesh, 0.05);
    std::vector<std::pair<uint64_t, int>> sorted(v.begin(), v.end());
    std::sort(sorted.begin(), sorted.end());
    std::vector<double> x, y, z, label;
    for (const auto& [k, l] : sorted) {
      const VoxelKey key{uint16_t(k >> 32), uint16_t(k >> 16), uint16_t(k)};
      const Eigen::Vector3d c = KeyToCoord(key, 0.05);
      x.push_back(c.x()), y.push_back(c.y()), z.push_back(c.z()), label.push_back(l);
    }
    PlyWriter w;
    w.AddElement("vertex", x.size());
    w.AddProperty("x", PlyType::kFloat32, x);
    w.AddProperty("y", PlyType::kFloat32, y);
    w.AddProperty("z", PlyType::kFloat32, z);
    w.AddProperty("label", PlyType::kUInt16, label);
    ASSERT_TRUE(w.Write((pred_ / "voxels.ply").string()).ok());
  }

  fs::path root_, gt_, pred_;
  Apartment apt_;
};

TEST_F(EvaluateEndToEnd, PerfectPredictionScoresHundredPercent) {
  WritePerfect();
  Result<EvalReport> r = Evaluate(pred_.string(), gt_.string());
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_DOUBLE_EQ(r->top_view.geometric_accuracy.value, 1.0);
  EXPECT_DOUBLE_EQ(r->voxels.accuracy.value, 1.0);
  EXPECT_DOUBLE_EQ(r->voxels.mean_iou.value, 1.0);
  EXPECT_DOUBLE_EQ(r->voxels.nyu4_global.value, 1.0);
  EXPECT_EQ(r->voxels.visible, r->voxels.gt_voxels);
  EXPECT_DOUBLE_EQ(r->rooms.recall.value, 1.0);
  EXPECT_DOUBLE_EQ(r->rooms.precision.value, 1.0);
  EXPECT_DOUBLE_EQ(r->room_types.global.value, 1.0);
  EXPECT_DOUBLE_EQ(r->room_types.average.value, 1.0);
  // Top-view semantics from surface voxels: the highest surface voxel of a column is the top of what
  // stands there, whose label the ground truth also holds, except where a thin item (a picture, a door
  // leaf) shares a voxel column with a wall. Nearly all pixels agree.
  EXPECT_GT(r->top_view.semantic_global.value, 0.97) << r->Table();
  std::printf("%s", r->Table().c_str());
  EXPECT_NE(r->ToJson().find("\"geometric_accuracy\""), std::string::npos);
}

TEST_F(EvaluateEndToEnd, MissingPredictionFilesAreReportedAbsent) {
  Result<EvalReport> r = Evaluate(pred_.string(), gt_.string());
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_FALSE(r->top_view.geometric_accuracy.present);
  EXPECT_FALSE(r->voxels.accuracy.present);
  EXPECT_FALSE(r->rooms.recall.present);
  EXPECT_FALSE(r->room_types.global.present);
  EXPECT_NE(r->Table().find("absent"), std::string::npos);
  const std::string json = r->ToJson();
  EXPECT_NE(json.find("\"present\": false"), std::string::npos);
  EXPECT_EQ(json.find("\"value\""), std::string::npos) << "no number is reported for an absent metric";
}

TEST_F(EvaluateEndToEnd, BadGroundTruthDirectoryIsAnInputError) {
  Result<EvalReport> r = Evaluate(pred_.string(), (root_ / "nowhere").string());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(r.status().message().find("gt.json"), std::string::npos) << r.status().message();
}

}  // namespace
}  // namespace semvox
