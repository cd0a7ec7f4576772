// Box scores of a real scan (eval/box_eval.h) on a hand-built run: a voxels.ply and gt.json written here,
// with a rotation in axis_align_matrix, give exactly known recalls; malformed inputs give one error line.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/labels.h"
#include "core/ply.h"
#include "eval/box_eval.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

using namespace nyu40;

// Scan frame -> aligned frame: 90° about +z, then (1, 2, -0.5): aligned = (1 - y, x + 2, z - 0.5).
const char* kMatrix = "[[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, -0.5], [0, 0, 0, 1]]";

struct Voxel {
  double ax, ay, az;  // Aligned frame, metres.
  int label;
};

// Inverse of kMatrix: scan = (ay - 2, 1 - ax, az + 0.5).
Eigen::Vector3d ToScan(const Voxel& v) { return {v.ay - 2.0, 1.0 - v.ax, v.az + 0.5}; }

// The synthetic run (aligned frame; 5 cm voxels, centres on z = -0.025 + k * 0.05):
//   box 0 table (7) at (2, 2, 0.5):  table, desk, desk, chair -> recall 3/4 (desk stands for table)
//   box 1 desk (14) at (3, 3, 0.5):  table, wall              -> recall 1/2 (table stands for desk)
//   box 2 table (7) at (4, 4, 0.5):  wall, wall               -> recall 0
//   box 3 sofa (6)  at (5, 5, 0.5):  empty                    -> excluded from the mean
//   box 4 bed (4)   at (1, 1, 0.05): 4 bed voxels on the floor level -> recall 1, excluded from the floor band
//   floor level z = 0.025: 16 floor + 4 wall; z = 0.075: 8 floor + 2 chair; z = -0.025: 3 wall (noise below the
//   floor, < 25 % of the densest level); z = 0.125: 5 floor (above the band).
// Mean box recall (3/4 + 1/2 + 0 + 1) / 4; table class 3/6; floor recall 24/30; wall share 10/50.
std::vector<Voxel> SyntheticVoxels() {
  std::vector<Voxel> v;
  const auto box = [&](double c, double z, std::vector<int> labels) {
    for (size_t i = 0; i < labels.size(); ++i) v.push_back({c - 0.075 + 0.05 * double(i), c + 0.025, z, labels[i]});
  };
  box(2.0, 0.475, {kTable, kDesk, kDesk, kChair});
  box(3.0, 0.475, {kTable, kWall});
  box(4.0, 0.475, {kWall, kWall});
  box(1.0, 0.025, {kBed, kBed, kBed, kBed});
  for (int i = 0; i < 20; ++i) v.push_back({0.025 + 0.05 * i, 0.325, 0.025, i < 16 ? kFloor : kWall});
  for (int i = 0; i < 10; ++i) v.push_back({0.025 + 0.05 * i, 0.375, 0.075, i < 8 ? kFloor : kChair});
  for (int i = 0; i < 3; ++i) v.push_back({0.025 + 0.05 * i, 0.425, -0.025, kWall});
  for (int i = 0; i < 5; ++i) v.push_back({0.025 + 0.05 * i, 0.475, 0.125, kFloor});
  return v;
}

const char* kGroundTruth = R"({
  "axis_align_matrix": MATRIX,
  "boxes_in_aligned_frame": [
    {"class": "table", "nyu40": 7, "centre_size": [2, 2, 0.5, 0.4, 0.4, 0.2]},
    {"class": "desk", "nyu40": 14, "centre_size": [3, 3, 0.5, 0.4, 0.4, 0.2]},
    {"class": "table", "nyu40": 7, "centre_size": [4, 4, 0.5, 0.4, 0.4, 0.2]},
    {"class": "sofa", "nyu40": 6, "centre_size": [5, 5, 0.5, 0.4, 0.4, 0.2]},
    {"class": "bed", "nyu40": 4, "centre_size": [1, 1, 0.05, 0.2, 0.2, 0.1]}
  ],
  "scene_type": "test"
})";

std::string GroundTruthText() {
  std::string s = kGroundTruth;
  s.replace(s.find("MATRIX"), 6, kMatrix);
  return s;
}

// Writes voxels.ply as `semvox run` does (x y z float, colour, ushort label, ...); `with_label` false drops the label.
void WriteVoxelsPly(const std::string& path, const std::vector<Voxel>& voxels, bool with_label = true) {
  std::vector<double> x, y, z, label, zero;
  for (const Voxel& v : voxels) {
    const Eigen::Vector3d p = ToScan(v);
    x.push_back(p.x()), y.push_back(p.y()), z.push_back(p.z()), label.push_back(v.label), zero.push_back(0);
  }
  PlyWriter w;
  w.AddElement("vertex", voxels.size());
  w.AddProperty("x", PlyType::kFloat32, x);
  w.AddProperty("y", PlyType::kFloat32, y);
  w.AddProperty("z", PlyType::kFloat32, z);
  w.AddProperty("red", PlyType::kUInt8, zero);
  if (with_label) w.AddProperty("label", PlyType::kUInt16, label);
  w.AddProperty("confidence", PlyType::kFloat32, zero);
  ASSERT_TRUE(w.Write(path).ok());
}

TEST(BoxEval, SyntheticRunGivesExactRecalls) {
  testing::ScratchDir dir("box_eval");
  WriteVoxelsPly(dir.File("voxels.ply"), SyntheticVoxels());
  testing::WriteText(dir.File("gt.json"), GroundTruthText());
  Result<RunVoxels> voxels = ReadRunVoxels(dir.File("voxels.ply"));
  ASSERT_TRUE(voxels.ok()) << voxels.status().message();
  Result<BoxGroundTruth> gt = ReadBoxGroundTruth(dir.File("gt.json"));
  ASSERT_TRUE(gt.ok()) << gt.status().message();
  ASSERT_EQ(gt->boxes.size(), 5u);

  const BoxEvalReport r = EvaluateBoxes(*voxels, *gt);
  EXPECT_EQ(r.occupied, 50u);
  ASSERT_EQ(r.boxes.size(), 5u);
  EXPECT_EQ(r.boxes[0].voxels, 4u);
  EXPECT_DOUBLE_EQ(r.boxes[0].recall.value, 0.75);  // Desk voxels count for a table box.
  EXPECT_DOUBLE_EQ(r.boxes[1].recall.value, 0.5);   // And a table voxel for a desk box.
  EXPECT_TRUE(r.boxes[2].recall.present);
  EXPECT_DOUBLE_EQ(r.boxes[2].recall.value, 0.0);
  EXPECT_EQ(r.boxes[3].voxels, 0u);
  EXPECT_FALSE(r.boxes[3].recall.present);  // Empty box: no recall, not in the mean.
  EXPECT_DOUBLE_EQ(r.boxes[4].recall.value, 1.0);
  EXPECT_EQ(r.boxes_scored, 4);
  ASSERT_TRUE(r.mean_box_recall.present);
  EXPECT_DOUBLE_EQ(r.mean_box_recall.value, (0.75 + 0.5 + 0.0 + 1.0) / 4.0);

  // Top labels: most frequent first, ties to the lower id (chair 5 before table 7).
  ASSERT_EQ(r.boxes[0].top.size(), 3u);
  EXPECT_EQ(r.boxes[0].top[0].label, kDesk);
  EXPECT_EQ(r.boxes[0].top[0].count, 2u);
  EXPECT_EQ(r.boxes[0].top[1].label, kChair);
  EXPECT_EQ(r.boxes[0].top[2].label, kTable);

  // Per class: the two table boxes pooled.
  ASSERT_EQ(r.per_class.count("table"), 1u);
  EXPECT_EQ(r.per_class.at("table").boxes, 2);
  EXPECT_EQ(r.per_class.at("table").voxels, 6u);
  EXPECT_DOUBLE_EQ(r.per_class.at("table").recall.value, 0.5);
  EXPECT_DOUBLE_EQ(r.per_class.at("desk").recall.value, 0.5);
  EXPECT_FALSE(r.per_class.at("sofa").recall.present);

  // Floor: the level z = 0.025 is the lowest dense one, so the floor is its lower face, z = 0; the band
  // [0, 0.1) holds the levels 0.025 and 0.075 minus the bed box's voxels.
  EXPECT_NEAR(r.floor_z_m, 0.0, 1e-6);
  EXPECT_EQ(r.floor_band_voxels, 30u);
  EXPECT_DOUBLE_EQ(r.floor_recall.value, 24.0 / 30.0);
  EXPECT_DOUBLE_EQ(r.wall_share.value, 10.0 / 50.0);
  EXPECT_FALSE(r.rooms_present.present);  // EvaluateBoxes alone reads no rooms.geojson.
}

TEST(BoxEval, WithoutTheRotationTheBoxesAreMissed) {
  // The same voxels scored with an identity matrix land outside every box: the matrix is applied.
  std::vector<Eigen::Vector3d> centres;
  std::vector<int> labels;
  for (const Voxel& v : SyntheticVoxels()) centres.push_back(ToScan(v)), labels.push_back(v.label);
  Result<BoxGroundTruth> gt = ParseBoxGroundTruth(GroundTruthText(), "gt.json");
  ASSERT_TRUE(gt.ok());
  gt->axis_align = Eigen::Matrix4d::Identity();
  const BoxEvalReport r = EvaluateBoxes(RunVoxels{centres, labels, 0.05, {}}, *gt);
  EXPECT_EQ(r.boxes_scored, 0);
  EXPECT_FALSE(r.mean_box_recall.present);
}

TEST(BoxEval, FloorHeightIsTheLowerFaceOfTheLowestDenseLevel) {
  // 2 noise voxels at 0.0, 10 at 0.05, 40 at 0.10, 100 at 2.5 (a ceiling): 10 >= 25 % of 40? no, of 100? no;
  // 40 >= 25: the floor is the level 0.10, lower face 0.075.
  std::vector<double> z;
  for (int i = 0; i < 2; ++i) z.push_back(0.0);
  for (int i = 0; i < 10; ++i) z.push_back(0.05);
  for (int i = 0; i < 40; ++i) z.push_back(0.10);
  for (int i = 0; i < 100; ++i) z.push_back(2.5);
  EXPECT_NEAR(EstimateFloorHeight(z, 0.05), 0.075, 1e-9);
  EXPECT_EQ(EstimateFloorHeight({}, 0.05), 0.0);
}

TEST(BoxEval, RunDirectoryAddsRoomsAndSeconds) {
  testing::ScratchDir dir("box_eval_run");
  WriteVoxelsPly(dir.File("voxels.ply"), SyntheticVoxels());
  testing::WriteText(dir.File("gt.json"), GroundTruthText());
  testing::WriteText(dir.File("summary.json"), R"({"voxel_size_m": 0.05, "seconds": {"load": 0.5, "classify": 2.25, "total": 3.0}})");
  testing::WriteText(dir.File("rooms.geojson"), R"({"type": "FeatureCollection", "features": [
    {"type": "Feature", "id": 1, "geometry": null, "properties": {"id": 1, "type": "kitchen", "type_id": 6, "area_m2": 7.5}},
    {"type": "Feature", "id": 2, "geometry": null, "properties": {"id": 2, "type": "bedroom", "type_id": 2, "area_m2": 11.25}}]})");
  Result<BoxEvalReport> r = EvaluateRunAgainstBoxes(dir.path().string(), dir.File("gt.json"));
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_DOUBLE_EQ(r->mean_box_recall.value, 0.5625);
  ASSERT_TRUE(r->rooms_present.present);
  ASSERT_EQ(r->rooms.size(), 2u);
  EXPECT_EQ(r->rooms[0].type, "kitchen");
  EXPECT_DOUBLE_EQ(r->rooms[1].area_m2, 11.25);
  ASSERT_EQ(r->seconds.size(), 3u);
  EXPECT_EQ(r->seconds[1].first, "classify");  // File order.
  EXPECT_DOUBLE_EQ(r->seconds[2].second, 3.0);
  const std::string table = r->Table();
  EXPECT_NE(table.find("mean box recall"), std::string::npos);
  EXPECT_NE(table.find("kitchen 7.5 m2"), std::string::npos);
  EXPECT_NE(table.find("total 3.0"), std::string::npos);
  EXPECT_NE(r->ToJson().find("\"mean_box_recall\""), std::string::npos);
  // Without rooms.geojson the rooms are reported absent, not empty.
  std::filesystem::remove(dir.File("rooms.geojson"));
  r = EvaluateRunAgainstBoxes(dir.path().string(), dir.File("gt.json"));
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(r->rooms_present.present);
}

// Each malformed gt.json gives kInvalidInput whose one line names the file and the field.
TEST(BoxEval, MalformedGroundTruthGivesAnErrorNamingTheField) {
  const std::string good = GroundTruthText();
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? s : s.replace(at, from.size(), to);
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{ not json", "not valid JSON"},
      {"[1, 2]", "top level"},
      {with("axis_align_matrix", "matrix"), "missing field axis_align_matrix"},
      {with("[0, 0, 0, 1]]", "[0, 0, 0]]"), "axis_align_matrix: expected 4 rows of 4 numbers"},
      {with("[0, -1, 0, 1]", "[0, \"a\", 0, 1]"), "axis_align_matrix[0][1]"},
      {with("boxes_in_aligned_frame", "boxes"), "missing field boxes_in_aligned_frame"},
      {with("[2, 2, 0.5, 0.4, 0.4, 0.2]", "[2, 2, 0.5, 0.4, 0.4]"), "boxes_in_aligned_frame[0].centre_size: expected 6 numbers"},
      {with("[3, 3, 0.5, 0.4, 0.4, 0.2]", "[3, 3, 0.5, 0.4, -0.4, 0.2]"), "boxes_in_aligned_frame[1].centre_size[4]: negative size"},
      {with("\"nyu40\": 14", "\"nyu40\": \"desk\""), "boxes_in_aligned_frame[1].nyu40"},
      {with("\"nyu40\": 14", "\"nyu40\": 41"), "outside 1..40"},
      {with("\"class\": \"sofa\", ", ""), "boxes_in_aligned_frame[3].class"},
  };
  for (const auto& [text, expected] : cases) {
    Result<BoxGroundTruth> gt = ParseBoxGroundTruth(text, "some/gt.json");
    ASSERT_FALSE(gt.ok()) << expected;
    EXPECT_EQ(gt.status().code(), StatusCode::kInvalidInput);
    EXPECT_NE(gt.status().message().find("some/gt.json: "), std::string::npos) << gt.status().message();
    EXPECT_NE(gt.status().message().find(expected), std::string::npos) << gt.status().message();
    EXPECT_EQ(gt.status().message().find('\n'), std::string::npos) << gt.status().message();
  }
  EXPECT_TRUE(ParseBoxGroundTruth(good, "gt.json").ok());
}

// SUN RGB-D style boxes (gt_boxes.tsv): yawed about +z in the scan's frame, classes by NYU40 name or alias.
TEST(BoxEval, SunRgbdBoxesAreTurnedByTheirYaw) {
  const std::string tsv =
      "instance\tclass_id\tclass_name\tcx\tcy\tcz\tdx\tdy\tdz\tyaw_rad\tpoints_inside\n"
      "0\t7\tnight_stand\t0\t0\t0.5\t2\t0.2\t1\t0.7853981633974483\t10\n"
      "1\t0\tbed\t5\t5\t0.5\t1\t1\t1\t0\t20\n";
  Result<BoxGroundTruth> gt = ParseSunRgbdBoxes(tsv, "gt_boxes.tsv");
  ASSERT_TRUE(gt.ok()) << gt.status().message();
  ASSERT_EQ(gt->boxes.size(), 2u);
  EXPECT_EQ(gt->boxes[0].nyu40, 32);  // night_stand -> night stand.
  EXPECT_EQ(gt->boxes[0].class_name, "night_stand");
  EXPECT_EQ(gt->boxes[1].nyu40, kBed);
  EXPECT_TRUE(gt->axis_align.isIdentity(0.0));
  // A 2 m x 0.2 m box turned by 45 degrees: along the diagonal, not along x.
  const GroundTruthBox& b = gt->boxes[0];
  EXPECT_TRUE(b.Contains(Eigen::Vector3d(0.6, 0.6, 0.5)));
  EXPECT_FALSE(b.Contains(Eigen::Vector3d(0.6, -0.6, 0.5)));
  EXPECT_FALSE(b.Contains(Eigen::Vector3d(0.9, 0.0, 0.5)));
  EXPECT_FALSE(b.Contains(Eigen::Vector3d(0.6, 0.6, 1.1)));
  // Scored: voxels on the diagonal count for the night stand, the one off it for nothing.
  RunVoxels v;
  v.centres = {{0.3, 0.3, 0.5}, {-0.3, -0.3, 0.5}, {0.5, -0.5, 0.5}, {5, 5, 0.2}};
  v.labels = {32, kDresser, 32, kBed};
  const BoxEvalReport r = EvaluateBoxes(v, *gt);
  EXPECT_EQ(r.boxes[0].voxels, 2u);
  EXPECT_DOUBLE_EQ(r.boxes[0].recall.value, 0.5);
  EXPECT_DOUBLE_EQ(r.boxes[1].recall.value, 1.0);

  // Bad input: one line naming the file and what is wrong.
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "empty file"},
      {"class_name\tcx\tcy\tcz\tdx\tdy\tdz\n", "no column yaw_rad"},
      {"class_name\tcx\tcy\tcz\tdx\tdy\tdz\tyaw_rad\nbed\t1\t2\t3\t1\t1\tx\t0\n", "line 2, dz: \"x\" is not a finite number"},
      {"class_name\tcx\tcy\tcz\tdx\tdy\tdz\tyaw_rad\nbed\t1\t2\t3\t1\t-1\t1\t0\n", "line 2, dy: negative size"},
      {"class_name\tcx\tcy\tcz\tdx\tdy\tdz\tyaw_rad\nspaceship\t1\t2\t3\t1\t1\t1\t0\n", "\"spaceship\" is not a NYU40 class name"},
      {"class_name\tcx\tcy\tcz\tdx\tdy\tdz\tyaw_rad\nbed\t1\t2\n", "line 2: no cz field"},
  };
  for (const auto& [text, expected] : cases) {
    Result<BoxGroundTruth> bad = ParseSunRgbdBoxes(text, "some/gt_boxes.tsv");
    ASSERT_FALSE(bad.ok()) << expected;
    EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput);
    EXPECT_NE(bad.status().message().find("some/gt_boxes.tsv: "), std::string::npos) << bad.status().message();
    EXPECT_NE(bad.status().message().find(expected), std::string::npos) << bad.status().message();
    EXPECT_EQ(bad.status().message().find('\n'), std::string::npos) << bad.status().message();
  }
  // ReadBoxGroundTruth reads a .tsv path as this format.
  testing::ScratchDir dir("box_eval_sun");
  testing::WriteText(dir.File("gt_boxes.tsv"), tsv);
  Result<BoxGroundTruth> read = ReadBoxGroundTruth(dir.File("gt_boxes.tsv"));
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_EQ(read->boxes.size(), 2u);
}

TEST(BoxEval, MissingFilesAndUnlabelledVoxelsAreInvalidInput) {
  testing::ScratchDir dir("box_eval_bad");
  Result<BoxGroundTruth> gt = ReadBoxGroundTruth(dir.File("absent.json"));
  ASSERT_FALSE(gt.ok());
  EXPECT_EQ(gt.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(gt.status().message().find("absent.json"), std::string::npos);
  WriteVoxelsPly(dir.File("voxels.ply"), SyntheticVoxels(), /*with_label=*/false);
  Result<RunVoxels> v = ReadRunVoxels(dir.File("voxels.ply"));
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(v.status().message().find("no label property"), std::string::npos) << v.status().message();
  testing::WriteText(dir.File("gt.json"), GroundTruthText());
  Result<BoxEvalReport> r = EvaluateRunAgainstBoxes(dir.File("no_such_run"), dir.File("gt.json"));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidInput);
}

}  // namespace
}  // namespace semvox
