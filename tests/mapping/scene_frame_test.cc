// Canonical frame estimate (mapping/scene_frame.h): a generated apartment (seed 102)
// turned about z, tilted and shifted, as a mesh and as a cloud sampled from it without normals; the
// estimator must recover up within 0.3 degrees, the yaw (mod 90) within 0.5 degrees, the floor within
// 2 cm and the walls' phase within the voxel grid within 2.5 mm. Upside-down and 30-degree-tilted scans warn naming --up; an axis-aligned scene gives exactly the
// identity.
#include "mapping/scene_frame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "io/load_scene.h"
#include "mapping/cloud_geometry.h"
#include "scenegen/apartment.h"

namespace semvox {
namespace {

constexpr double kDeg = M_PI / 180.0;

const Mesh& ApartmentMesh() {
  static const Mesh mesh = [] {
    ApartmentOptions ao;
    ao.seed = 102;
    Result<Apartment> a = GenerateApartment(ao);
    EXPECT_TRUE(a.ok()) << a.status().message();
    return a.ok() ? a->mesh : Mesh();
  }();
  return mesh;
}

Scene MeshScene(const Eigen::Isometry3d& input_from_original) {
  Scene s;
  s.format = "ply";
  s.mesh = ApartmentMesh();
  TransformScene(input_from_original, &s);
  return s;
}

// Points sampled uniformly over the mesh's area (about `per_m2` per square metre), no normals, no colours.
Scene CloudScene(const Eigen::Isometry3d& input_from_original, double per_m2 = 300.0) {
  const Mesh& m = ApartmentMesh();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Scene s;
  s.format = "ply";
  double carry = 0;
  for (const auto& f : m.faces) {
    const Eigen::Vector3d a = m.vertices[f[0]].cast<double>(), b = m.vertices[f[1]].cast<double>(),
                          c = m.vertices[f[2]].cast<double>();
    carry += 0.5 * (b - a).cross(c - a).norm() * per_m2;
    for (; carry >= 1.0; carry -= 1.0) {
      double r1 = u01(rng), r2 = u01(rng);
      if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
      s.cloud.points.push_back((a + r1 * (b - a) + r2 * (c - a)).cast<float>());
    }
  }
  TransformScene(input_from_original, &s);
  return s;
}

// Turned by yaw about z, tilted by `tilt` about the horizontal axis (cos 40deg, sin 40deg, 0), shifted.
Eigen::Isometry3d Pose(double yaw_deg, double tilt_deg, const Eigen::Vector3d& shift) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.rotate(Eigen::AngleAxisd(tilt_deg * kDeg, Eigen::Vector3d(std::cos(40 * kDeg), std::sin(40 * kDeg), 0)));
  t.rotate(Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()));
  t.pretranslate(shift);
  return t;
}

double Mod90Diff(double a, double b) {
  double d = std::fmod(a - b, 90.0);
  if (d > 45) d -= 90;
  if (d <= -45) d += 90;
  return d;
}

void ExpectRecovers(const Scene& scene, const Eigen::Isometry3d& input_from_original, double yaw_deg, const char* what) {
  const SceneFrame f = EstimateSceneFrame(scene);
  const Eigen::Vector3d true_up = input_from_original.linear() * Eigen::Vector3d::UnitZ();
  const double up_err = std::acos(std::clamp(f.up.dot(true_up), -1.0, 1.0)) / kDeg;
  const double yaw_err = Mod90Diff(f.yaw_deg, yaw_deg);
  // The floor (z = 0 originally) along the levelled up: the height of the shifted origin along the true up.
  const double true_floor = true_up.dot(input_from_original.translation());
  std::printf("[%s] up error %.4f deg, tilt %.3f deg, yaw %.4f deg (true %.1f, error %.4f), floor %.4f m (true %.4f), %.3f s\n",
              what, up_err, f.tilt_deg, f.yaw_deg, yaw_deg, yaw_err, f.floor_z, true_floor, f.seconds);
  EXPECT_TRUE(f.up_found);
  EXPECT_TRUE(f.levelled);
  EXPECT_FALSE(f.upside_down);
  EXPECT_LT(up_err, 0.3);
  EXPECT_TRUE(f.yaw_found);
  EXPECT_LT(std::fabs(yaw_err), 0.5);
  EXPECT_TRUE(f.floor_found);
  EXPECT_NEAR(f.floor_z, true_floor, 0.02);
  // Composed with the pose, the canonical frame is the original up to a turn by a multiple of 90 degrees
  // about z and a horizontal shift.
  const Eigen::Isometry3d m = f.canonical_from_input * input_from_original;
  EXPECT_NEAR((m.linear() * Eigen::Vector3d::UnitZ()).z(), 1.0, 1 - std::cos(0.3 * kDeg));
  const Eigen::Vector3d x = m.linear() * Eigen::Vector3d::UnitX();
  EXPECT_LT(std::fabs(Mod90Diff(std::atan2(x.y(), x.x()) / kDeg, 0.0)), 0.5);
  EXPECT_NEAR(m.translation().z(), 0.0, 0.02);
  // The horizontal shift puts the walls where the original's lie in the voxel grid (on voxel boundaries, the
  // generator's walls at whole multiples of 5 cm): whole voxels apart, within 2.5 mm (scan noise and the
  // tilt's residual move the estimate by a millimetre or two).
  const double res = SceneFrameOptions().bin_m;
  for (int axis = 0; axis < 2; ++axis)
    EXPECT_LT(std::fabs(std::remainder(m.translation()[axis], res)), 0.0025) << what << " axis " << axis << ": " << m.translation().transpose();
  EXPECT_TRUE(f.warnings.empty());  // 2 degrees is below the warning threshold.
}

TEST(SceneFrame, MeshTurnedTiltedShifted) {
  for (double yaw : {17.0, 33.0}) {
    const Eigen::Isometry3d pose = Pose(yaw, 2.0, Eigen::Vector3d(1.3, -2.1, 0.8));
    ExpectRecovers(MeshScene(pose), pose, yaw, yaw == 17.0 ? "mesh 17" : "mesh 33");
  }
}

TEST(SceneFrame, CloudWithoutNormalsTurnedTiltedShifted) {
  for (double yaw : {17.0, 33.0}) {
    const Eigen::Isometry3d pose = Pose(yaw, 2.0, Eigen::Vector3d(1.3, -2.1, 0.8));
    ExpectRecovers(CloudScene(pose), pose, yaw, yaw == 17.0 ? "cloud 17" : "cloud 33");
  }
}

// Shifted by less than a voxel and nothing else: by default a level, axis-aligned scan keeps its grid; with
// phase_only_when_turned off the canonical frame shifts it back onto the grid (x, y; the floor's own rule
// takes z back to 0), and a shift under snap_shift_m is left alone.
TEST(SceneFrame, WallsAreShiftedOntoVoxelBoundaries) {
  const Eigen::Isometry3d pose = Pose(0.0, 0.0, Eigen::Vector3d(0.013, -0.021, 0.0));
  EXPECT_TRUE(EstimateSceneFrame(MeshScene(pose)).shift.isZero());
  SceneFrameOptions always;
  always.phase_only_when_turned = false;
  const SceneFrame f = EstimateSceneFrame(MeshScene(pose), always);
  std::printf("shift (%.4f %.4f) m, phase concentration (%.2f %.2f)\n", f.shift.x(), f.shift.y(), f.phase_concentration.x(),
              f.phase_concentration.y());
  EXPECT_NEAR(f.shift.x(), 0.013, 0.0015);
  EXPECT_NEAR(f.shift.y(), -0.021, 0.0015);
  EXPECT_GT(f.phase_concentration.minCoeff(), 0.3);
  const Eigen::Vector3d back = (f.canonical_from_input * pose).translation();
  EXPECT_LT(back.head<2>().cwiseAbs().maxCoeff(), 0.0015) << back.transpose();
  SceneFrameOptions off = always;
  off.wall_phase = false;
  EXPECT_TRUE(EstimateSceneFrame(MeshScene(pose), off).shift.isZero());
  const SceneFrame tiny = EstimateSceneFrame(MeshScene(Pose(0.0, 0.0, Eigen::Vector3d(0.001, 0.0, 0.0))), always);
  EXPECT_TRUE(tiny.shift.isZero()) << tiny.shift.transpose();
}

TEST(SceneFrame, AxisAlignedGivesExactlyTheIdentity) {
  const SceneFrame f = EstimateSceneFrame(MeshScene(Eigen::Isometry3d::Identity()));
  EXPECT_TRUE(f.identity());
  EXPECT_TRUE(f.up_found);
  EXPECT_EQ(f.yaw_deg, 0.0);
  EXPECT_EQ(f.floor_z, 0.0);
  EXPECT_TRUE(f.warnings.empty());
  // The bundled demo apartment, as `semvox run` loads it: level, axis-aligned, the floor at 0: exactly the
  // identity, although its walls' phase is half a voxel (their mean lies at voxel centres; measured
  // concentration 0.54 on both axes). With phase_only_when_turned off it is shifted by half a voxel, nothing else.
  Result<Scene> demo = LoadScene(std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply", LoadOptions());
  ASSERT_TRUE(demo.ok()) << demo.status().message();
  EXPECT_TRUE(EstimateSceneFrame(demo.value()).identity());
  SceneFrameOptions always;
  always.phase_only_when_turned = false;
  const SceneFrame d = EstimateSceneFrame(demo.value(), always);
  EXPECT_TRUE(d.canonical_from_input.linear().isIdentity()) << d.canonical_from_input.matrix();
  EXPECT_EQ(d.canonical_from_input.translation().z(), 0.0);
  for (int axis = 0; axis < 2; ++axis) EXPECT_NEAR(std::fabs(d.shift[axis]), 0.025, 0.001) << d.shift.transpose();
  EXPECT_GT(d.phase_concentration.minCoeff(), 0.4);
  EXPECT_TRUE(d.warnings.empty());
}

bool NamesUp(const SceneFrame& f) {
  for (const auto& w : f.warnings)
    if (w.find("--up") != std::string::npos) return true;
  return false;
}

TEST(SceneFrame, UpsideDownWarnsAndKeepsTheInput) {
  Eigen::Isometry3d flip = Eigen::Isometry3d::Identity();
  flip.rotate(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  for (const Scene& scene : {MeshScene(flip), CloudScene(flip, 150.0)}) {
    const SceneFrame f = EstimateSceneFrame(scene);
    EXPECT_TRUE(f.upside_down) << (scene.is_mesh() ? "mesh" : "cloud");
    EXPECT_FALSE(f.levelled);
    EXPECT_GT(f.tilt_deg, 179.0);
    EXPECT_TRUE(NamesUp(f));
    EXPECT_TRUE(f.canonical_from_input.linear().isIdentity(0.0));
  }
}

// A fused cloud often has no ceiling (ScanNet's rarely do; the randomised training scans drop it in 40 %).
// The floor, the largest horizontal plane at one end, still tells up from down, upright and turned over.
TEST(SceneFrame, CloudWithoutCeilingIsUprightAndTurnedOverIsUpsideDown) {
  const Scene full = CloudScene(Eigen::Isometry3d::Identity(), 150.0);
  float top = -1e9f;
  for (const auto& p : full.cloud.points) top = std::max(top, p.z());
  Scene open = full;
  open.cloud.points.clear();
  for (const auto& p : full.cloud.points)
    if (p.z() < top - 0.05f) open.cloud.points.push_back(p);
  ASSERT_LT(open.cloud.points.size(), full.cloud.points.size());
  const SceneFrame f = EstimateSceneFrame(open);
  EXPECT_FALSE(f.upside_down);
  EXPECT_LT(f.tilt_deg, 1.0);
  EXPECT_TRUE(f.warnings.empty()) << f.warnings.front();
  Eigen::Isometry3d flip = Eigen::Isometry3d::Identity();
  flip.rotate(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  TransformScene(flip, &open);
  EXPECT_TRUE(EstimateSceneFrame(open).upside_down);
}

TEST(SceneFrame, ThirtyDegreeTiltIsLevelledWithAWarning) {
  const Eigen::Isometry3d pose = Pose(0.0, 30.0, Eigen::Vector3d::Zero());
  const SceneFrame f = EstimateSceneFrame(MeshScene(pose));
  EXPECT_TRUE(f.levelled);
  EXPECT_NEAR(f.tilt_deg, 30.0, 0.3);
  EXPECT_TRUE(NamesUp(f));
  // Beyond max_level_deg the input up is kept, with a warning.
  const SceneFrame g = EstimateSceneFrame(MeshScene(Pose(0.0, 60.0, Eigen::Vector3d::Zero())));
  EXPECT_FALSE(g.levelled);
  EXPECT_TRUE(NamesUp(g));
}

TEST(SceneFrame, TransformSceneMovesPointsAndRotatesNormals) {
  Scene s;
  s.cloud.points = {Eigen::Vector3f(1, 0, 0)};
  s.cloud.normals = {Eigen::Vector3f(1, 0, 0)};
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  t.pretranslate(Eigen::Vector3d(0, 0, 2));
  TransformScene(t, &s);
  EXPECT_NEAR((s.cloud.points[0] - Eigen::Vector3f(0, 1, 2)).norm(), 0.0f, 1e-6f);
  EXPECT_NEAR((s.cloud.normals[0] - Eigen::Vector3f(0, 1, 0)).norm(), 0.0f, 1e-6f);
}

// The real ScanNet studio (a cloud, +Z up, walls turned by about 19 degrees) from ../shared/data; skipped when
// absent. ScanNet's axis_align_matrix (gt.json) turns it by -19.0 degrees about z and lowers it by 0.064 m.
// The estimate is compared with it modulo 90 degrees; the wall-normal azimuths of the two wall families are
// printed on their own (are the walls square?).
TEST(SceneFrame, ScanNetStudio) {
  const std::string dir = std::string(SEMVOX_SOURCE_DIR) + "/../shared/data/scannet_scene0000_00";
  if (!std::filesystem::exists(dir + "/scene0000_00.ply")) GTEST_SKIP() << dir << " absent";
  Result<Scene> scene = LoadScene(dir + "/scene0000_00.ply");
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  const SceneFrame f = EstimateSceneFrame(scene.value());
  std::printf("studio: %zu points; up (%.4f %.4f %.4f), tilt %.3f deg, yaw %.3f deg, floor %.4f m, %zu warnings, %.3f s\n",
              scene->cloud.points.size(), f.up.x(), f.up.y(), f.up.z(), f.tilt_deg, f.yaw_deg, f.floor_z, f.warnings.size(),
              f.seconds);
  // Azimuth of wall normals (after levelling) per family, circular means within 5 degrees of yaw and yaw + 90.
  Scene levelled = scene.value();
  Eigen::Isometry3d level = Eigen::Isometry3d::Identity();
  level.linear() = f.canonical_from_input.linear();  // Includes Rz(-yaw): azimuths relative to the yaw.
  TransformScene(level, &levelled);
  const CloudGeometry geo = EstimateCloudGeometry(levelled.cloud, 12);
  for (double family : {0.0, 90.0}) {
    double c = 0, sn = 0, w = 0;
    for (const auto& n : geo.normals) {
      if (std::fabs(n.z()) > std::sin(10 * kDeg)) continue;
      const double a = std::atan2(n.y(), n.x()) / kDeg;
      const double d = std::remainder(a - family, 180.0);
      if (std::fabs(d) > 5) continue;
      c += std::cos(2 * d * kDeg), sn += std::sin(2 * d * kDeg), w += 1;
    }
    std::printf("studio: walls with normals near %.0f deg: %.0f points, mean offset %.3f deg\n", family, w,
                std::atan2(sn, c) / 2 / kDeg);
  }
  EXPECT_TRUE(f.up_found);
  EXPECT_LT(f.tilt_deg, 3.0);
  EXPECT_TRUE(f.yaw_found);
  EXPECT_LT(std::fabs(Mod90Diff(f.yaw_deg, 19.0)), 1.5);  // ScanNet's own alignment is an estimate too.
  EXPECT_NEAR(f.floor_z, 0.05, 0.05);
  EXPECT_LT(f.seconds, 1.0);
  // Upside down (turned by 180 degrees about x): the furniture tells, as on generated apartments.
  Scene flipped = scene.value();
  Eigen::Isometry3d flip = Eigen::Isometry3d::Identity();
  flip.rotate(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  TransformScene(flip, &flipped);
  const SceneFrame g = EstimateSceneFrame(flipped);
  EXPECT_TRUE(g.upside_down);
  EXPECT_TRUE(NamesUp(g));
}

// A room lower than 2 m with its whole ceiling scanned (the generated apartment squashed to 70 % of its height:
// ceilings at 1.8-1.9 m), whose ceiling outweighs the floor the furniture hides: the extreme planes alone would
// call it upside down, so the furniture votes too, and it is upright; turned over, upside down.
TEST(SceneFrame, LowCeilingLargerThanTheVisibleFloorIsUpright) {
  Scene low = MeshScene(Eigen::Isometry3d::Identity());
  for (auto& v : low.mesh.vertices) v.z() *= 0.7f;
  // Every other floor face dropped: the scanner saw about half the floor.
  std::vector<Eigen::Vector3i> faces;
  int floor_faces = 0;
  for (const auto& f : low.mesh.faces) {
    bool on_floor = true;
    for (int k = 0; k < 3; ++k) on_floor = on_floor && std::fabs(low.mesh.vertices[size_t(f[k])].z()) < 0.005f;
    if (!on_floor || floor_faces++ % 2 == 0) faces.push_back(f);
  }
  ASSERT_GT(floor_faces, 10);
  low.mesh.faces = faces;
  low.mesh.face_attributes.clear();
  const SceneFrame f = EstimateSceneFrame(low);
  EXPECT_FALSE(f.upside_down);
  EXPECT_LT(f.tilt_deg, 1.0);
  Eigen::Isometry3d flip = Eigen::Isometry3d::Identity();
  flip.rotate(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  TransformScene(flip, &low);
  EXPECT_TRUE(EstimateSceneFrame(low).upside_down);
}

// One real RGB-D view of a bedroom (SUN RGB-D frame 000017 from ../shared/data; upright depth coordinates, +z
// up, the floor about 1.2 m below the camera); skipped when absent. The bed's top is the highest horizontal
// plane and lies only a metre above the floor: no ceiling, so the furniture in the upper half of the range
// says nothing, and the floor at the low end says upright. It was called upside down (and left unlevelled)
// until 2026-12-06. The ground-truth boxes' bottoms (bed, night stand) lie at -1.20 and -1.25 m.
TEST(SceneFrame, SunRgbdBedroomViewIsUprightAndLevelled) {
  const std::string path = std::string(SEMVOX_SOURCE_DIR) + "/../shared/data/sunrgbd_000017/000017_points.ply";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " absent";
  Result<Scene> scene = LoadScene(path);
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  const SceneFrame f = EstimateSceneFrame(scene.value());
  std::printf("SUN RGB-D 000017: up (%.4f %.4f %.4f), tilt %.3f deg, floor %.4f m, %zu warnings\n", f.up.x(), f.up.y(), f.up.z(),
              f.tilt_deg, f.floor_z, f.warnings.size());
  EXPECT_TRUE(f.up_found);
  EXPECT_FALSE(f.upside_down);
  EXPECT_TRUE(f.levelled);
  EXPECT_GT(f.up.z(), 0.99);
  EXPECT_LT(f.tilt_deg, 4.0);
  EXPECT_TRUE(f.floor_found);
  EXPECT_NEAR(f.floor_z, -1.2, 0.1);
  for (const std::string& w : f.warnings) EXPECT_EQ(w.find("upside down"), std::string::npos) << w;
  // Turned over, it is upside down.
  Scene flipped = scene.value();
  Eigen::Isometry3d flip = Eigen::Isometry3d::Identity();
  flip.rotate(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  TransformScene(flip, &flipped);
  EXPECT_TRUE(EstimateSceneFrame(flipped).upside_down);
}

}  // namespace
}  // namespace semvox
