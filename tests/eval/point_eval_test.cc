// Point scores of a real scan (eval/point_eval.h) on a hand-built run: a voxels.ply and a labelled PLY written
// here give exactly known accuracies and recalls; malformed inputs give one clear error.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/labels.h"
#include "core/ply.h"
#include "eval/point_eval.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

using namespace nyu40;

Status WriteCloud(const std::string& path, const std::vector<Eigen::Vector3d>& p, const std::vector<int>& labels,
                  bool with_label = true) {
  PlyWriter w;
  w.AddElement("vertex", p.size());
  std::vector<double> x, y, z, l(labels.begin(), labels.end());
  for (const auto& q : p) {
    x.push_back(q.x());
    y.push_back(q.y());
    z.push_back(q.z());
  }
  w.AddProperty("x", PlyType::kFloat32, x);
  w.AddProperty("y", PlyType::kFloat32, y);
  w.AddProperty("z", PlyType::kFloat32, z);
  if (with_label) w.AddProperty("label", PlyType::kUInt16, l);
  return w.Write(path);
}

// Voxels (5 cm): a floor row of 4 (floor, floor, floor, chair) at z = 0.025, a table at (1, 0, 0.7), a wall voxel
// at (0, 1, 1). Points:
//   floor: 4 points, one over each floor-row voxel (3 right), 1 point 0.2 m under the row (unmatched) -> 3/5
//   desk: 2 points 3 cm from the table voxel (table stands for desk) -> 2/2
//   wall: 1 point 7 cm from the wall voxel (matched, right), 1 point 8 cm away (unmatched) -> 1/2
//   label 0: 3 points, skipped.
// Accuracy 6/9, matched 7/9, class mean (3/5 + 2/2 + 1/2) / 3, floor recall 3/5, wall share 1/6.
TEST(PointEval, KnownRunGivesKnownScores) {
  testing::ScratchDir dir("point_eval");
  const std::string run = dir.File("run");
  std::filesystem::create_directories(run);
  ASSERT_TRUE(WriteCloud(run + "/voxels.ply",
                         {{0.025, 0.025, 0.025}, {0.075, 0.025, 0.025}, {0.125, 0.025, 0.025}, {0.175, 0.025, 0.025},
                          {1.025, 0.025, 0.725}, {0.025, 1.025, 1.025}},
                         {kFloor, kFloor, kFloor, kChair, kTable, kWall})
                  .ok());
  ASSERT_TRUE(WriteCloud(dir.File("gt.ply"),
                         {{0.03, 0.02, 0.0}, {0.08, 0.03, 0.0}, {0.12, 0.02, 0.0}, {0.17, 0.03, 0.0}, {0.1, 0.0, -0.2},
                          {1.055, 0.025, 0.725}, {1.025, 0.055, 0.725}, {0.095, 1.025, 1.025}, {0.025, 1.105, 1.025},
                          {5, 5, 5}, {0.03, 0.02, 0.0}, {1, 0, 0.7}},
                         {kFloor, kFloor, kFloor, kFloor, kFloor, kDesk, kDesk, kWall, kWall, 0, 0, 0})
                  .ok());
  Result<PointEvalReport> r = EvaluateRunAgainstPoints(run, dir.File("gt.ply"));
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_EQ(r->points, 9u);
  EXPECT_EQ(r->occupied, 6u);
  EXPECT_NEAR(r->accuracy.value, 6.0 / 9.0, 1e-12);
  EXPECT_NEAR(r->matched.value, 7.0 / 9.0, 1e-12);
  EXPECT_NEAR(r->mean_class_recall.value, (3.0 / 5.0 + 1.0 + 0.5) / 3.0, 1e-12);
  ASSERT_TRUE(r->floor_recall.present);
  EXPECT_NEAR(r->floor_recall.value, 0.6, 1e-12);
  EXPECT_NEAR(r->wall_share.value, 1.0 / 6.0, 1e-12);
  ASSERT_EQ(r->per_class.size(), 3u);
  const PointClassScore& floor = r->per_class.at(kFloor);
  EXPECT_EQ(floor.unmatched, 1u);
  ASSERT_EQ(floor.top.size(), 3u);
  EXPECT_EQ(floor.top[0].label, kFloor);
  EXPECT_EQ(floor.top[0].count, 3u);
  EXPECT_EQ(r->per_class.at(kWall).unmatched, 1u);
  EXPECT_FALSE(r->rooms_present.present);  // No rooms.geojson in the run.
  EXPECT_EQ(r->confidence.scored, 0u);      // No confidence in voxels.ply.
  // The report names the unmatched points and the classes.
  EXPECT_NE(r->Table().find("unmatched (1)"), std::string::npos) << r->Table();
  EXPECT_NE(r->ToJson().find("\"mean_class_recall\""), std::string::npos);
}

TEST(PointEval, BadGroundTruthIsRefusedNamingTheFile) {
  testing::ScratchDir dir("point_eval_bad");
  const std::string run = dir.File("run");
  std::filesystem::create_directories(run);
  ASSERT_TRUE(WriteCloud(run + "/voxels.ply", {{0, 0, 0}}, {kFloor}).ok());
  // No label property.
  ASSERT_TRUE(WriteCloud(dir.File("nolabel.ply"), {{0, 0, 0}}, {kFloor}, false).ok());
  Result<PointEvalReport> r = EvaluateRunAgainstPoints(run, dir.File("nolabel.ply"));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("nolabel.ply"), std::string::npos);
  EXPECT_NE(r.status().message().find("no label property"), std::string::npos);
  // A label outside NYU40.
  ASSERT_TRUE(WriteCloud(dir.File("big.ply"), {{0, 0, 0}}, {41}).ok());
  r = EvaluateRunAgainstPoints(run, dir.File("big.ply"));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("not a NYU40 id"), std::string::npos) << r.status().message();
  // Only unlabelled points.
  ASSERT_TRUE(WriteCloud(dir.File("zero.ply"), {{0, 0, 0}}, {0}).ok());
  r = EvaluateRunAgainstPoints(run, dir.File("zero.ply"));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("no labelled point"), std::string::npos);
  // A missing file, a missing run.
  EXPECT_FALSE(EvaluateRunAgainstPoints(run, dir.File("absent.ply")).ok());
  r = EvaluateRunAgainstPoints(dir.File("absent"), dir.File("zero.ply"));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("not a directory"), std::string::npos);
}

}  // namespace
}  // namespace semvox
