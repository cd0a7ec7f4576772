#include "render/raycaster.h"

#include <gtest/gtest.h>

#include <cmath>

namespace semvox {
namespace {

// Two triangles forming the square [0,1]^2 at z = 0.
Mesh UnitSquare() {
  Mesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

TEST(Raycaster, HitsSquareAtExactDistanceWithFacingNormal) {
  Result<Raycaster> rc = Raycaster::FromMesh(UnitSquare());
  ASSERT_TRUE(rc.ok()) << rc.status().message();
  EXPECT_FALSE(rc->is_cloud());
  EXPECT_EQ(rc->num_primitives(), 2u);
  Ray ray{{0.25f, 0.75f, 2.0f}, {0, 0, -1}};
  RayHit hit = rc->Intersect(ray);
  ASSERT_TRUE(hit.hit());
  EXPECT_NEAR(hit.distance, 2.0f, 1e-6f);
  EXPECT_EQ(hit.primitive, 1);
  EXPECT_EQ(hit.normal, Eigen::Vector3f(0, 0, 1));
  const Eigen::Vector3d p = rc->HitPoint(ray, hit);
  EXPECT_EQ(p.z(), 0.0);  // Exactly on the face.
  EXPECT_NEAR(p.x(), 0.25, 1e-6);
  EXPECT_NEAR(p.y(), 0.75, 1e-6);
  // From below, the normal flips to face the origin.
  RayHit below = rc->Intersect(Ray{{0.5f, 0.2f, -1.0f}, {0, 0, 1}});
  ASSERT_TRUE(below.hit());
  EXPECT_EQ(below.normal, Eigen::Vector3f(0, 0, -1));
  EXPECT_EQ(below.primitive, 0);
}

TEST(Raycaster, MissesOutsideAndBeyondRange) {
  Result<Raycaster> rc = Raycaster::FromMesh(UnitSquare());
  ASSERT_TRUE(rc.ok());
  EXPECT_FALSE(rc->Intersect(Ray{{2, 2, 1}, {0, 0, -1}}).hit());
  Ray short_ray{{0.5f, 0.5f, 1.0f}, {0, 0, -1}};
  short_ray.t_max = 0.5f;
  RayHit h = rc->Intersect(short_ray);
  EXPECT_FALSE(h.hit());
  EXPECT_TRUE(std::isinf(h.distance));
}

TEST(Raycaster, BatchEqualsSingleRays) {
  Result<Raycaster> rc = Raycaster::FromMesh(UnitSquare());
  ASSERT_TRUE(rc.ok());
  std::vector<Ray> rays;
  for (int i = 0; i < 1000; ++i) {  // Not a multiple of 16: exercises partial packets.
    const float x = -0.5f + 2.0f * float(i % 37) / 36.0f, y = -0.5f + 2.0f * float(i / 37) / 27.0f;
    rays.push_back(Ray{{x, y, 1.0f}, Eigen::Vector3f(0.1f, -0.05f, -1.0f)});
  }
  std::vector<RayHit> hits;
  rc->Intersect(rays, &hits);
  ASSERT_EQ(hits.size(), rays.size());
  int n_hit = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const RayHit single = rc->Intersect(rays[i]);
    ASSERT_EQ(single.primitive, hits[i].primitive) << i;
    if (!single.hit()) continue;
    ++n_hit;
    EXPECT_FLOAT_EQ(single.distance, hits[i].distance);
    EXPECT_FLOAT_EQ(single.u, hits[i].u);
    EXPECT_FLOAT_EQ(single.v, hits[i].v);
  }
  EXPECT_GT(n_hit, 100);
  EXPECT_LT(n_hit, 1000);
}

TEST(Raycaster, RejectsBadMeshes) {
  EXPECT_FALSE(Raycaster::FromMesh(Mesh{}).ok());
  Mesh bad = UnitSquare();
  bad.faces.push_back({0, 1, 7});
  Result<Raycaster> rc = Raycaster::FromMesh(bad);
  ASSERT_FALSE(rc.ok());
  EXPECT_EQ(rc.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(rc.status().message().find("face 2"), std::string::npos) << rc.status().message();
}

TEST(Raycaster, CloudDiscsCloseAPlane) {
  // A 1 m square sampled every 2 cm at z = 0: rays between samples must still hit a disc.
  PointCloud cloud;
  for (int i = 0; i <= 50; ++i)
    for (int j = 0; j <= 50; ++j) cloud.points.push_back({0.02f * i, 0.02f * j, 0.0f});
  Result<Raycaster> rc = Raycaster::FromCloud(cloud);
  ASSERT_TRUE(rc.ok()) << rc.status().message();
  EXPECT_TRUE(rc->is_cloud());
  ASSERT_EQ(rc->point_radii().size(), cloud.points.size());
  for (float r : rc->point_radii()) EXPECT_GT(r, 0.0099f);
  int hits = 0, total = 0;
  for (float x = 0.1f; x < 0.9f; x += 0.0137f)
    for (float y = 0.1f; y < 0.9f; y += 0.0173f) {
      ++total;
      Ray ray{{x, y, 1.0f}, {0, 0, -1}};
      RayHit h = rc->Intersect(ray);
      if (!h.hit()) continue;
      ++hits;
      EXPECT_NEAR(h.distance, 1.0f, 1e-4f);
      EXPECT_NEAR(std::abs(h.normal.z()), 1.0f, 1e-4f);
      EXPECT_NEAR(rc->HitPoint(ray, h).z(), 0.0, 1e-4);
    }
  EXPECT_EQ(hits, total);
}

TEST(Raycaster, MergedCloudSquaresCloseAPlaneAndReportPoints) {
  // The same 2 cm samples merged into 5 cm cells and drawn as squares: fewer primitives, the plane still
  // closed, and every hit reports one of the cloud's points (colours and labels come from it).
  PointCloud cloud;
  for (int i = 0; i <= 50; ++i)
    for (int j = 0; j <= 50; ++j) cloud.points.push_back({0.02f * i, 0.02f * j, 0.0f});
  RaycasterOptions options;
  options.cloud_cell_m = 0.05;
  options.point_radius_factor = 0.75;
  for (bool squares : {false, true}) {
    options.cloud_squares = squares;
    Result<Raycaster> rc = Raycaster::FromCloud(cloud, options);
    ASSERT_TRUE(rc.ok()) << rc.status().message();
    EXPECT_EQ(rc->num_primitives(), cloud.points.size());
    EXPECT_LT(rc->point_radii().size(), cloud.points.size() / 4);  // 21 x 21 cells of 2.5 x 2.5 points.
    int hits = 0, total = 0;
    for (float x = 0.1f; x < 0.9f; x += 0.0137f)
      for (float y = 0.1f; y < 0.9f; y += 0.0173f) {
        ++total;
        Ray ray{{x, y, 1.0f}, {0, 0, -1}};
        RayHit h = rc->Intersect(ray);
        if (!h.hit()) continue;
        ++hits;
        ASSERT_GE(h.primitive, 0);
        ASSERT_LT(size_t(h.primitive), cloud.points.size());
        // The reported point lies in the hit's neighbourhood (its cell or the next).
        EXPECT_LT((cloud.points[size_t(h.primitive)].head<2>() - Eigen::Vector2f(x, y)).norm(), 0.1f);
        EXPECT_NEAR(h.distance, 1.0f, 1e-4f);
        EXPECT_NEAR(std::abs(h.normal.z()), 1.0f, 1e-4f);
      }
    EXPECT_EQ(hits, total) << (squares ? "squares" : "discs");
  }
  options.cloud_cell_m = -1;
  EXPECT_FALSE(Raycaster::FromCloud(cloud, options).ok());
}

}  // namespace
}  // namespace semvox
