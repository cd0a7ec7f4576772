// Canonical frame end to end: `semvox run` on a generated apartment turned by 17 degrees about z, tilted
// by 2 degrees and shifted by (1.3, -2.1, 0.8) m finds the same rooms and the same labels as on the original.
// The transformed run works in its estimated canonical frame and writes voxels.ply in the input (transformed)
// frame; each of its voxels, mapped back into the original frame, is matched to the nearest voxel of the
// original run (agreement), and both runs are scored against the ground-truth mesh (visible-voxel accuracy,
// docs/metrics.md (b)); the moved run is scored on its own canonical grid (ground-truth mesh moved there), so
// that resampling one grid onto the other does not count as an error.
// Measured 2026-12-02 (Release, seed 102 with 2 rooms): rooms 2 / 2; nearest-voxel label agreement 0.936
// (boundary voxels of a 17-degree-turned grid match a neighbour of another label, and the views differ);
// visible-voxel accuracy 0.815 original, 0.798 moved (0.775 resampled onto the original grid): 1.7 points
// apart, within the 2 points of the issue (agreement >= 0.98 is not reached). Estimated yaw 17.000, tilt
// 1.985 degrees. Earlier variants: seed 102 with one room 0.783 vs 0.768; seed 103, one room, 0.802 vs 0.799.
// Two runs, 50-80 s in Release; skipped under the sanitizers.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "core/mesh_ply.h"
#include "core/ply.h"
#include "core/voxel_key.h"
#include "eval/evaluate.h"
#include "io/load_scene.h"
#include "mapping/scene_frame.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

int RunSemvox(const std::string& args, const std::string& log) {
  const int rc = std::system((std::string(SEMVOX_BINARY) + " " + args + " > " + log + " 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in, nullptr, false);
}

struct Voxels {
  std::vector<Eigen::Vector3d> centres;
  std::vector<int> labels;
};

Voxels ReadVoxels(const std::string& path) {
  Voxels v;
  Result<PlyData> ply = ReadPly(path);
  EXPECT_TRUE(ply.ok()) << ply.status().message();
  if (!ply.ok()) return v;
  const PlyElement* e = ply->Find("vertex");
  for (size_t i = 0; i < e->count; ++i) {
    v.centres.emplace_back(e->Find("x")->values[i], e->Find("y")->values[i], e->Find("z")->values[i]);
    v.labels.push_back(int(e->Find("label")->values[i]));
  }
  return v;
}

uint64_t KeyOf(const Eigen::Vector3d& p, double res) {
  return VoxelKey{uint16_t(CoordToKeyIndex(p.x(), res)), uint16_t(CoordToKeyIndex(p.y(), res)),
                  uint16_t(CoordToKeyIndex(p.z(), res))}.Pack();
}

TEST(FrameCli, TurnedTiltedShiftedApartmentGivesTheSameRoomsAndLabels) {
#ifdef SEMVOX_SANITIZE_BUILD
  GTEST_SKIP() << "two full runs take minutes under the sanitizers";
#endif
  const auto t0 = std::chrono::steady_clock::now();
  testing::ScratchDir dir("frame_cli");
  const std::string gt = dir.File("gt"), a = dir.File("a"), b = dir.File("b"), log = dir.File("log.txt");
  // The test's short configuration, with every candidate classified: the greedy view cover (the default)
  // picks other views in a turned frame, so it would test the cover's choice as well as the frame.
  // Measured with the cover (Release, 2026-12-02): visible-voxel accuracy 0.835 original, 0.799 moved
  // (agreement 0.930): the original frame gained 2 points over classifying every view, the moved one kept
  // its accuracy. Every view classified, since the canonical frame fixes the walls' phase in the voxel grid
  // and the viewpoint squares start at the grid's corner (2026-12-04): 0.815 / 0.806, agreement 0.983; with
  // semantic.layout_frequency_power 1, 0.841 / 0.835, agreement 0.975 (without the two, 0.841 / 0.809).
  const std::string config = dir.File("frame.yaml");
  testing::WriteText(config, testing::ReadText(std::string(SEMVOX_SOURCE_DIR) + "/tests/data/semantic.yaml") +
                                 "  view_selection: all\n");
  ASSERT_EQ(RunSemvox("generate --seed 102 --set apartment.min_rooms=2 --set apartment.max_rooms=3 -o " + gt, log), 0) << testing::ReadText(log);
  Result<Scene> scene = LoadScene(gt + "/mesh.ply");
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // moved_from_original
  pose.rotate(Eigen::AngleAxisd(2.0 * M_PI / 180, Eigen::Vector3d(std::cos(0.7), std::sin(0.7), 0)));
  pose.rotate(Eigen::AngleAxisd(17.0 * M_PI / 180, Eigen::Vector3d::UnitZ()));
  pose.pretranslate(Eigen::Vector3d(1.3, -2.1, 0.8));
  TransformScene(pose, &scene.value());
  ASSERT_TRUE(WriteMeshPly(dir.File("moved.ply"), scene->mesh).ok());

  ASSERT_EQ(RunSemvox("run " + gt + "/mesh.ply -o " + a + " --config " + config, log), 0) << testing::ReadText(log);
  ASSERT_EQ(RunSemvox("run " + dir.File("moved.ply") + " -o " + b + " --config " + config, log), 0) << testing::ReadText(log);
  const nlohmann::json sa = ReadJson(a + "/summary.json"), sb = ReadJson(b + "/summary.json");
  ASSERT_FALSE(sa.is_discarded() || sb.is_discarded());
  // The original is axis-aligned with the floor at 0: nothing is applied. The moved one is levelled and turned.
  EXPECT_FALSE(sa["frame"]["applied"].get<bool>());
  EXPECT_TRUE(sb["frame"]["applied"].get<bool>());
  const double yaw = sb["frame"]["yaw_deg"].get<double>();
  EXPECT_NEAR(std::remainder(yaw - 17.0, 90.0), 0.0, 0.5);
  EXPECT_NEAR(sb["frame"]["tilt_deg"].get<double>(), 2.0, 0.3);
  // summary.json's floor is in the input frame: the moved floor's height along the up, 0.8 m and a bit.
  const Eigen::Vector3d up = pose.linear() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(sb["floor"]["z"].get<double>(), up.dot(pose.translation()), 0.03);
  EXPECT_EQ(sa["rooms"]["rooms"].get<int>(), sb["rooms"]["rooms"].get<int>());

  // Labels: the moved run's voxels back in the original frame against the original run's.
  const double res = 0.05;
  const Voxels va = ReadVoxels(a + "/voxels.ply"), vb = ReadVoxels(b + "/voxels.ply");
  ASSERT_GT(va.centres.size(), 1000u);
  std::unordered_map<uint64_t, size_t> index_a;
  for (size_t i = 0; i < va.centres.size(); ++i) index_a.emplace(KeyOf(va.centres[i], res), i);
  const Eigen::Isometry3d original_from_moved = pose.inverse();
  size_t matched = 0, agree = 0;
  VoxelLabels pred_a, pred_b;
  for (size_t i = 0; i < va.centres.size(); ++i) pred_a.emplace(KeyOf(va.centres[i], res), va.labels[i]);
  for (size_t i = 0; i < vb.centres.size(); ++i) {
    const Eigen::Vector3d p = original_from_moved * vb.centres[i];
    pred_b.emplace(KeyOf(p, res), vb.labels[i]);
    double best = 1e9;
    int label = -1;
    const int64_t kx = CoordToKeyIndex(p.x(), res), ky = CoordToKeyIndex(p.y(), res), kz = CoordToKeyIndex(p.z(), res);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = index_a.find(VoxelKey{uint16_t(kx + dx), uint16_t(ky + dy), uint16_t(kz + dz)}.Pack());
          if (it == index_a.end()) continue;
          const double d = (va.centres[it->second] - p).norm();
          if (d < best) best = d, label = va.labels[it->second];
        }
    if (label < 0) continue;
    ++matched;
    agree += label == vb.labels[i];
  }
  const double agreement = matched ? double(agree) / double(matched) : 0.0;
  Result<Scene> gt_mesh = LoadScene(gt + "/gt_mesh.ply");
  ASSERT_TRUE(gt_mesh.ok()) << gt_mesh.status().message();
  const VoxelLabels truth = VoxelizeLabeledMesh(gt_mesh->mesh, res);
  // Each run is scored on its own grid: the moved run's in its canonical frame, with the ground-truth mesh
  // moved there (no resampling of one grid onto the other).
  Eigen::Isometry3d input_from_canonical = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) input_from_canonical.matrix()(r, c) = sb["frame"]["input_from_canonical"][r][c].get<double>();
  const Eigen::Isometry3d canonical_from_input = input_from_canonical.inverse();
  Scene truth_b = gt_mesh.value();
  TransformScene(canonical_from_input * pose, &truth_b);
  VoxelLabels pred_b_own;
  for (size_t i = 0; i < vb.centres.size(); ++i) pred_b_own.emplace(KeyOf(canonical_from_input * vb.centres[i], res), vb.labels[i]);
  const VoxelScores score_a = ScoreVoxels(truth, pred_a), score_b = ScoreVoxels(VoxelizeLabeledMesh(truth_b.mesh, res), pred_b_own);
  const VoxelScores score_b_resampled = ScoreVoxels(truth, pred_b);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("rooms %d / %d; %zu / %zu voxels; matched %zu (%.3f), label agreement %.4f; visible-voxel accuracy original "
              "%.4f, moved %.4f (resampled onto the original grid %.4f); yaw %.3f deg, tilt %.3f deg, floor %.4f m; %.0f s\n",
              sa["rooms"]["rooms"].get<int>(), sb["rooms"]["rooms"].get<int>(), va.centres.size(), vb.centres.size(), matched,
              double(matched) / double(std::max<size_t>(1, vb.centres.size())), agreement, score_a.accuracy.value,
              score_b.accuracy.value, score_b_resampled.accuracy.value, yaw, sb["frame"]["tilt_deg"].get<double>(),
              sb["frame"]["floor_z_input"].get<double>(), seconds);
  EXPECT_GT(double(matched), 0.9 * double(vb.centres.size()));
  // The criterion: agreement >= 0.98, or accuracy against the ground truth within 2 points.
  EXPECT_TRUE(agreement >= 0.98 || std::fabs(score_a.accuracy.value - score_b.accuracy.value) <= 0.02)
      << "agreement " << agreement << ", accuracy " << score_a.accuracy.value << " vs " << score_b.accuracy.value;
  // Both copies on the same grid up to whole voxels, seen from the same viewpoints: most voxels agree.
  EXPECT_GT(agreement, 0.95);
  // Grid outputs of the moved run are on its canonical grid; occupancy.yaml carries the turn.
  const std::string yaml = testing::ReadText(b + "/occupancy.yaml");
  EXPECT_EQ(yaml.find(", 0.0]"), std::string::npos) << yaml;
}

}  // namespace
}  // namespace semvox
