// Viewpoints and the views stage: placement in free space, filters, views.json, and coverage of the
// demo apartment's surface by the kept views.
#include "render/views.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "io/load_scene.h"
#include "mapping/voxelizer.h"

namespace semvox {
namespace {

// A voxel map by hand: a 4 m x 3 m x 2.5 m room of free voxels (with a pillar) inside a shell of
// occupied voxels, floor at 0 and ceiling at 2.5.
VoxelMap HandMadeMap() {
  VoxelMap map;
  const double res = 0.1;
  map.grid = VoxelGrid(res, {kKeyOffset - 1, kKeyOffset - 1, kKeyOffset - 1}, {42, 32, 27});
  for (size_t i = 0; i < map.grid.size(); ++i) {
    const auto c = map.grid.Cell(i);
    const bool shell = c[0] == 0 || c[1] == 0 || c[2] == 0 || c[0] == 41 || c[1] == 31 || c[2] == 26;
    const bool pillar = c[0] >= 20 && c[0] < 23 && c[1] >= 10 && c[1] < 13;
    map.grid.set_state(i, shell || pillar ? VoxelState::kOccupied : VoxelState::kFree);
  }
  map.floor_found = map.ceiling_found = true;
  map.floor_z = 0.0;
  map.ceiling_z = 2.5;
  return map;
}

TEST(PlaceViewpoints, MidHeightInFreeSpaceWithClearance) {
  const VoxelMap map = HandMadeMap();
  ViewsOptions options;
  options.grid_spacing_m = 1.0;
  options.wall_clearance_m = 0.45;
  double z = 0;
  const std::vector<Eigen::Vector3d> positions = PlaceViewpoints(map, options, &z);
  EXPECT_NEAR(z, 1.25, 1e-12);  // Halfway between floor and ceiling.
  ASSERT_GE(positions.size(), 6u);
  const VoxelGrid& g = map.grid;
  for (const auto& p : positions) {
    EXPECT_EQ(p.z(), z);
    const auto cell = g.CellOf(p);
    ASSERT_TRUE(g.Contains(cell[0], cell[1], cell[2]));
    EXPECT_EQ(g.state(g.Index(cell[0], cell[1], cell[2])), VoxelState::kFree);
    // Brute force: no non-free voxel of the camera's layer within the clearance of the camera.
    for (int y = 0; y < g.dims()[1]; ++y)
      for (int x = 0; x < g.dims()[0]; ++x) {
        if (g.state(g.Index(x, y, cell[2])) == VoxelState::kFree) continue;
        const Eigen::Vector3d lo = g.CellCenter(x, y, cell[2]) - Eigen::Vector3d::Constant(0.5 * g.resolution());
        const Eigen::Vector3d hi = lo + Eigen::Vector3d::Constant(g.resolution());
        const Eigen::Vector2d nearest = p.head<2>().cwiseMax(lo.head<2>()).cwiseMin(hi.head<2>());
        EXPECT_GE((nearest - p.head<2>()).norm(), options.wall_clearance_m - 1e-9) << p.transpose();
      }
  }
  // Spread: at most one viewpoint per 1 m square, squares from the grid's lower corner (-0.1, -0.1).
  for (size_t i = 0; i < positions.size(); ++i)
    for (size_t j = i + 1; j < positions.size(); ++j)
      EXPECT_FALSE(std::floor(positions[i].x() + 0.1) == std::floor(positions[j].x() + 0.1) &&
                   std::floor(positions[i].y() + 0.1) == std::floor(positions[j].y() + 0.1));
  // Too much clearance: nowhere to stand.
  options.wall_clearance_m = 2.0;
  EXPECT_TRUE(PlaceViewpoints(map, options, &z).empty());
}

// The same map moved by whole voxels (another pose of one scan in its canonical frame) gets the same
// viewpoints moved with it: the squares start at the grid's corner, not at world multiples of the spacing.
TEST(PlaceViewpoints, MoveWithTheMapByWholeVoxels) {
  const VoxelMap map = HandMadeMap();
  VoxelMap moved = map;
  const std::array<int, 3> okey = map.grid.origin_key();
  moved.grid = VoxelGrid(map.grid.resolution(), {okey[0] + 7, okey[1] - 3, okey[2]}, map.grid.dims());
  for (size_t i = 0; i < map.grid.size(); ++i) moved.grid.set_state(i, map.grid.state(i));
  ViewsOptions options;
  options.grid_spacing_m = 1.0;
  options.wall_clearance_m = 0.45;
  const std::vector<Eigen::Vector3d> a = PlaceViewpoints(map, options, nullptr), b = PlaceViewpoints(moved, options, nullptr);
  ASSERT_GE(a.size(), 6u);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i)
    EXPECT_LT((b[i] - a[i] - Eigen::Vector3d(0.7, -0.3, 0.0)).norm(), 1e-9) << a[i].transpose() << " / " << b[i].transpose();
}

TEST(ViewsOptions, CheckNamesFieldValueAndConstraint) {
  ViewsOptions o;
  std::string error;
  EXPECT_TRUE(o.Check(&error));
  o.yaw_step_deg = 7;
  EXPECT_FALSE(o.Check(&error));
  EXPECT_NE(error.find("yaw_step_deg = 7. Violated constraint"), std::string::npos) << error;
  o = ViewsOptions{};
  o.horizontal_fov_deg = 180;
  EXPECT_FALSE(o.Check(&error));
  EXPECT_NE(error.find("horizontal_fov_deg = 180"), std::string::npos) << error;
  o = ViewsOptions{};
  o.pitch_deg = 60;
  o.tilted_ring_deg = 45;
  EXPECT_FALSE(o.Check(&error));
  EXPECT_NE(error.find("tilted_ring_deg"), std::string::npos) << error;
}

TEST(MeasureView, DropsEmptyTooCloseAndHomogeneousViews) {
  ViewsOptions options;
  RenderedView v;
  v.rgb = ImageRgb8(10, 10, 3);
  v.depth = ImageF32(10, 10, 1);
  v.primitive = Image<int32_t>(10, 10, 1, -1);
  ViewRecord r;
  MeasureView(v, options, &r);
  EXPECT_EQ(r.drop, ViewDrop::kEmpty);
  for (size_t i = 0; i < 100; ++i) {  // Every pixel hits at 0.5 m, in two colours.
    v.primitive.data[i] = 0;
    v.depth.data[i] = 0.5f;
    v.rgb.data[3 * i] = i % 2 ? 200 : 20;
  }
  MeasureView(v, options, &r);
  EXPECT_EQ(r.drop, ViewDrop::kTooClose);
  EXPECT_NEAR(r.median_depth_m, 0.5, 1e-6);
  for (size_t i = 0; i < 100; ++i) v.depth.data[i] = 3.0f;
  MeasureView(v, options, &r);
  EXPECT_TRUE(r.kept());
  EXPECT_NEAR(r.color_stddev, std::sqrt(90.0 * 90.0 / 3.0), 1e-6);  // Red channel std 90, others 0.
  for (size_t i = 0; i < 100; ++i) v.rgb.data[3 * i] = 128;
  MeasureView(v, options, &r);
  EXPECT_EQ(r.drop, ViewDrop::kHomogeneous);
  EXPECT_EQ(r.color_stddev, 0.0);
}

// NthSmallest finds the value std::nth_element puts at k: depths with many ties, zeros, a single value,
// and negative values (which take nth_element's path).
TEST(MeasureView, NthSmallestEqualsNthElement) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.f, 12.f);
  for (int trial = 0; trial < 40; ++trial) {
    const size_t n = 1 + size_t(rng() % 5000);
    std::vector<float> v(n);
    for (float& x : v) {
      x = u(rng);
      if (trial % 4 == 1) x = std::round(x * 4.f) / 4.f;  // Ties.
      if (trial % 4 == 2 && rng() % 3 == 0) x = 0.f;
      if (trial % 4 == 3 && rng() % 5 == 0) x = -x;
    }
    for (size_t k : {size_t(0), n / 2, n - 1, size_t(rng() % n)}) {
      std::vector<float> a = v, b = v;
      std::nth_element(b.begin(), b.begin() + ptrdiff_t(k), b.end());
      EXPECT_EQ(NthSmallest(&a, k), b[k]) << "n " << n << " k " << k << " trial " << trial;
    }
  }
}

TEST(RenderViews, DemoApartmentKeptViewsSeeItsSurface) {
  Result<Scene> scene = LoadScene(std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply");
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  Result<VoxelMap> map = Voxelize(scene.value(), VoxelizeOptions{});
  ASSERT_TRUE(map.ok()) << map.status().message();
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene.value());
  ASSERT_TRUE(renderer.ok());
  const ViewsOptions options;  // Defaults: 36 yaws of 10 degrees per viewpoint, 160x120.
  int sink_calls = 0;
  Result<ViewSet> views = RenderViews(renderer.value(), map.value(), options,
                                      [&](const ViewRecord& r, const RenderedView& v) {
                                        ++sink_calls;
                                        EXPECT_EQ(v.world_from_camera.matrix(), r.world_from_camera.matrix());
                                        return Status::Ok();
                                      });
  ASSERT_TRUE(views.ok()) << views.status().message();
  ASSERT_GE(views->positions.size(), 3u);  // At least one per room.
  EXPECT_EQ(views->views.size(), 36 * views->positions.size());
  EXPECT_EQ(sink_calls, int(views->views.size()));
  EXPECT_NEAR(views->view_z, 0.5 * (map->floor_z + map->ceiling_z), 1e-9);
  for (size_t i = 0; i < views->views.size(); ++i) {
    const ViewRecord& r = views->views[i];
    EXPECT_EQ(r.id, int(i));
    EXPECT_EQ(r.position, int(i / 36));
    EXPECT_EQ(r.yaw_deg, 10.0 * (i % 36));
    if (r.drop == ViewDrop::kTooClose) {
      EXPECT_LT(r.median_depth_m, options.min_median_depth_m);
    }
  }
  EXPECT_GT(views->num_kept(), views->views.size() / 2);

  const SurfaceCoverage cov = ComputeSurfaceCoverage(map->grid, views->voxel_seen);
  std::printf("%zu viewpoints, %zu of %zu views kept; they see %zu of %zu surface voxels (%.2f%%)\n",
              views->positions.size(), views->num_kept(), views->views.size(), cov.seen_voxels, cov.surface_voxels,
              100.0 * cov.fraction());
  EXPECT_GT(cov.surface_voxels, 10000u);
  EXPECT_GE(cov.fraction(), 0.95);
  // Kept views only see occupied voxels (the surface), never free space.
  size_t seen_free = 0, seen = 0;
  for (size_t i = 0; i < views->voxel_seen.size(); ++i) {
    seen += views->voxel_seen[i];
    seen_free += views->voxel_seen[i] && map->grid.state(i) == VoxelState::kFree;
  }
  EXPECT_LT(seen_free, seen / 1000) << seen_free << " of " << seen;

  const nlohmann::json j = nlohmann::json::parse(ViewsToJson(views.value(), options, true));
  EXPECT_EQ(j["intrinsics"]["width"], options.width);
  EXPECT_EQ(j["intrinsics"]["height"], options.height);
  EXPECT_EQ(j["views"].size(), views->views.size());
  EXPECT_EQ(j["counts"]["kept"], views->num_kept());
  const auto& first = j["views"][0];
  EXPECT_EQ(first["world_from_camera"].size(), 4u);
  EXPECT_EQ(first["thumbnail"], "views/view_00000.png");
  for (const auto& v : j["views"]) EXPECT_EQ(v["kept"].get<bool>(), v["drop_reason"] == "");

  // With the canonical frame turned and shifted against the input frame, positions and poses are mapped into
  // the input frame; yaws turn with the frame.
  Eigen::Isometry3d input_from_world = Eigen::Isometry3d::Identity();
  input_from_world.rotate(Eigen::AngleAxisd(20.0 * M_PI / 180, Eigen::Vector3d::UnitZ()));
  input_from_world.pretranslate(Eigen::Vector3d(1.0, 2.0, 0.5));
  const nlohmann::json m = nlohmann::json::parse(ViewsToJson(views.value(), options, false, input_from_world));
  EXPECT_NEAR(m["camera_z"].get<double>(), views->view_z + 0.5, 1e-9);
  const Eigen::Vector3d p0 = input_from_world * views->positions[0];
  EXPECT_NEAR(m["positions"][0][0].get<double>(), p0.x(), 1e-9);
  EXPECT_NEAR(m["positions"][0][1].get<double>(), p0.y(), 1e-9);
  for (size_t i = 0; i < 3; ++i) {
    const auto& v = m["views"][i];
    EXPECT_NEAR(std::remainder(v["yaw_deg"].get<double>() - views->views[i].yaw_deg - 20.0, 360.0), 0.0, 1e-6);
    EXPECT_NEAR(v["pitch_deg"].get<double>(), views->views[i].pitch_deg, 1e-6);
    const Eigen::Matrix4d t = (input_from_world * views->views[i].world_from_camera).matrix();
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) EXPECT_NEAR(v["world_from_camera"][r][c].get<double>(), t(r, c), 1e-9);
  }
}

}  // namespace
}  // namespace semvox
