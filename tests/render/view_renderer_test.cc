// ViewRenderer against an analytic box room: depth, normal, voxel key and emptiness of every pixel.
#include "render/view_renderer.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <optional>

#include "render/camera.h"

namespace semvox {
namespace {

constexpr double kVoxel = 0.05;
// The renderer's boundary convention (view_renderer.h): a point up to 1e-4 voxel below a boundary
// belongs to the voxel above it.
constexpr double kBoundaryTolerance = 1e-4 * kVoxel;
// In-plane coordinates of a hit carry float rounding (~1e-6 m at these distances); within this distance
// of a voxel boundary either neighbouring key is accepted along that axis.
constexpr double kAmbiguous = 1e-5;

// Axis-aligned quad at coordinate `c` on `axis`, spanning [lo, hi] on the two other axes, in one colour.
void AddQuad(Mesh* m, int axis, float c, Eigen::Vector2f lo, Eigen::Vector2f hi, Rgb8 color) {
  const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
  const int base = int(m->vertices.size());
  const Eigen::Vector2f corners[4] = {{lo.x(), lo.y()}, {hi.x(), lo.y()}, {hi.x(), hi.y()}, {lo.x(), hi.y()}};
  for (const auto& q : corners) {
    Eigen::Vector3f v;
    v[axis] = c;
    v[a1] = q.x();
    v[a2] = q.y();
    m->vertices.push_back(v);
    m->vertex_colors.push_back(color);
  }
  m->faces.push_back({base, base + 1, base + 2});
  m->faces.push_back({base, base + 2, base + 3});
}

// A box room [lo, hi]; the wall at x = hi.x has a rectangular hole [hole_lo, hole_hi] in (y, z) when given.
struct BoxRoom {
  Eigen::Vector3f lo{-1.513f, -1.21f, 0.0f};  // Floor exactly on a voxel boundary; walls off them.
  Eigen::Vector3f hi{2.487f, 1.79f, 2.6f};    // 2.6f = 2.5999999: a hair below a boundary.
  std::optional<std::pair<Eigen::Vector2f, Eigen::Vector2f>> hole;

  Mesh Build() const {
    Mesh m;
    for (int axis = 0; axis < 3; ++axis) {
      const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      const Eigen::Vector2f l(lo[a1], lo[a2]), h(hi[a1], hi[a2]);
      const Rgb8 color{uint8_t(60 + 40 * axis), 120, 200};
      AddQuad(&m, axis, lo[axis], l, h, color);
      if (axis == 0 && hole) {  // Four rectangles around the hole; (a1, a2) = (y, z).
        const auto& [hl, hh] = *hole;
        AddQuad(&m, 0, hi.x(), l, {h.x(), hl.y()}, color);
        AddQuad(&m, 0, hi.x(), {l.x(), hh.y()}, h, color);
        AddQuad(&m, 0, hi.x(), {l.x(), hl.y()}, {hl.x(), hh.y()}, color);
        AddQuad(&m, 0, hi.x(), {hh.x(), hl.y()}, {h.x(), hh.y()}, color);
      } else {
        AddQuad(&m, axis, hi[axis], l, h, color);
      }
    }
    return m;
  }
};

struct ExactHit {
  bool hit = false;
  bool ambiguous = false;  // Within kAmbiguous of an edge of the box or of the hole.
  int axis = 0;            // Axis the hit wall is perpendicular to.
  double t = 0;            // Ray parameter = depth (direction has camera z = 1).
  Eigen::Vector3d point, normal;
};

// The exact first hit of origin + t * dir with the (double) box room built from the float coordinates.
ExactHit Trace(const BoxRoom& room, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  ExactHit best;
  best.t = std::numeric_limits<double>::infinity();
  const Eigen::Vector3d lo = room.lo.cast<double>(), hi = room.hi.cast<double>();
  for (int axis = 0; axis < 3; ++axis) {
    if (d[axis] == 0) continue;
    const double plane = d[axis] > 0 ? hi[axis] : lo[axis];
    const double t = (plane - o[axis]) / d[axis];
    if (!(t > 0) || t >= best.t) continue;
    Eigen::Vector3d p = o + t * d;
    p[axis] = plane;
    bool inside = true, near_edge = false;
    for (int k = 0; k < 3; ++k) {
      if (k == axis) continue;
      inside &= p[k] >= lo[k] - kAmbiguous && p[k] <= hi[k] + kAmbiguous;
      near_edge |= std::abs(p[k] - lo[k]) < kAmbiguous || std::abs(p[k] - hi[k]) < kAmbiguous;
    }
    if (!inside) continue;
    best.t = t;
    best.axis = axis;
    best.point = p;
    best.normal = Eigen::Vector3d::Zero();
    best.normal[axis] = d[axis] > 0 ? -1.0 : 1.0;
    best.hit = true;
    best.ambiguous = near_edge;
    if (axis == 0 && d[0] > 0 && room.hole) {  // Through the hole?
      const auto& [hl, hh] = *room.hole;
      const bool in_hole = p.y() > hl.x() && p.y() < hh.x() && p.z() > hl.y() && p.z() < hh.y();
      const bool near_hole = std::abs(p.y() - hl.x()) < kAmbiguous || std::abs(p.y() - hh.x()) < kAmbiguous ||
                             std::abs(p.z() - hl.y()) < kAmbiguous || std::abs(p.z() - hh.y()) < kAmbiguous;
      best.ambiguous |= near_hole;
      best.hit = !in_hole;
    }
  }
  return best;
}

int64_t KeyIndex(double coord) { return CoordToKeyIndex(coord + kBoundaryTolerance, kVoxel); }
bool NearBoundary(double coord) {
  const double s = (coord + kBoundaryTolerance) / kVoxel;
  return std::abs(s - std::round(s)) * kVoxel < kAmbiguous;
}

struct Pose {
  Eigen::Vector3d position;
  double yaw, pitch;
};

const Pose kPoses[] = {{{0.3, 0.2, 1.3}, 0, 0},     {{0.3, 0.2, 1.3}, 37, -20}, {{-0.5, 1.0, 0.8}, 200, 35},
                       {{1.9, -0.9, 2.0}, 123, -60}, {{0.0, 0.0, 1.0}, 90, 0},   {{0.1, 0.1, 1.2}, 271, 10}};

TEST(ViewRenderer, BoxRoomDepthNormalKeyMatchExactGeometry) {
  BoxRoom room;
  Scene scene;
  scene.mesh = room.Build();
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(640, 480, 90);
  RenderOptions options;
  options.voxel_size_m = kVoxel;
  RenderedView view;
  size_t checked = 0, ambiguous_pixels = 0, ambiguous_axes = 0;
  for (const Pose& pose : kPoses) {
    const Eigen::Isometry3d world_from_camera = WorldFromCameraYawPitch(pose.position, pose.yaw, pose.pitch);
    ASSERT_TRUE(renderer->Render(camera, world_from_camera, options, &view).ok());
    ASSERT_EQ(view.rgb.width, 640);
    ASSERT_EQ(view.depth.height, 480);
    EXPECT_EQ(view.hit_pixels, size_t(640 * 480));  // A closed room: every pixel hits.
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        const Eigen::Vector3d d = world_from_camera.linear() * camera.PixelRay(x, y);
        const ExactHit e = Trace(room, pose.position, d);
        ASSERT_TRUE(e.hit);
        if (e.ambiguous) {  // On an edge of the room: either face is right.
          ++ambiguous_pixels;
          continue;
        }
        ASSERT_TRUE(view.hit(x, y)) << x << "," << y;
        ++checked;
        EXPECT_NEAR(view.depth.at(x, y), e.t, 1e-3) << x << "," << y;  // Within 1 mm.
        for (int k = 0; k < 3; ++k) ASSERT_EQ(view.normal.at(x, y, k), float(e.normal[k])) << x << "," << y;
        const VoxelKey key = view.voxel_key.at(x, y);
        const uint16_t got[3] = {key.x, key.y, key.z};
        for (int k = 0; k < 3; ++k) {
          const int64_t want = KeyIndex(e.point[k]);
          if (k != e.axis && NearBoundary(e.point[k])) {  // Float rounding inside the face: +-1 allowed.
            ++ambiguous_axes;
            ASSERT_LE(std::abs(int64_t(got[k]) - want), 1) << x << "," << y << " axis " << k;
            continue;
          }
          // The axis perpendicular to the wall is always exact (the hit point lies on the wall).
          ASSERT_EQ(int64_t(got[k]), want) << x << "," << y << " axis " << k << " coord " << e.point[k];
        }
        const Rgb8 c = scene.mesh.vertex_colors[scene.mesh.faces[view.primitive.at(x, y)][0]];
        EXPECT_EQ(view.rgb.at(x, y, 0), c.r);
      }
  }
  EXPECT_GT(checked, size_t(0.99 * std::size(kPoses) * 640 * 480));
  EXPECT_LT(ambiguous_axes, checked / 1000);
  std::printf("checked %zu pixels; %zu on room edges, %zu in-plane key coordinates within 10 um of a boundary\n",
              checked, ambiguous_pixels, ambiguous_axes);
}

// Render builds each 4 x 4 packet's ray directions from a per-column and a per-row part and traces it as two
// 8-ray packets; the directions must be the bits of the plain per-pixel product rot * (x, y, 1) (x, y the
// pixel centre on the z = 1 plane), and the hits those of the same 16 rays traced as one packet the plain
// way (Raycaster): the same faces at the same depths, pixel by pixel.
TEST(ViewRenderer, PacketRaysEqualThePlainPerPixelProduct) {
  BoxRoom room;
  room.hole = {{Eigen::Vector2f(-0.4f, 0.7f), Eigen::Vector2f(0.5f, 1.9f)}};
  Scene scene;
  scene.mesh = room.Build();
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(72, 52, 75);  // Whole 4 x 4 packets.
  RenderOptions options;
  options.voxel_size_m = kVoxel;
  RenderedView view;
  for (const Pose& pose : kPoses) {
    const Eigen::Isometry3d world_from_camera = WorldFromCameraYawPitch(pose.position, pose.yaw, pose.pitch);
    ASSERT_TRUE(renderer->Render(camera, world_from_camera, options, &view).ok());
    const Eigen::Matrix3f rot = world_from_camera.linear().cast<float>();
    const Eigen::Vector3f org = world_from_camera.translation().cast<float>();
    // The rays in Render's packet order: 4 x 4 pixel blocks, row by row inside a block.
    std::vector<Ray> rays;
    std::vector<std::pair<int, int>> pixel;
    for (int sy = 0; sy < camera.height; sy += 4)
      for (int sx = 0; sx < camera.width; sx += 4)
        for (int lane = 0; lane < 16; ++lane) {
          const int x = sx + lane % 4, y = sy + lane / 4;
          const float xs = float((x + 0.5 - camera.cx) / camera.fx), ys = float((y + 0.5 - camera.cy) / camera.fy);
          rays.push_back(Ray{org, rot * Eigen::Vector3f(xs, ys, 1.0f), 0.0f, float(options.max_depth_m)});
          pixel.emplace_back(x, y);
        }
    std::vector<RayHit> hits(rays.size());
    renderer->raycaster().IntersectSerial(rays, hits);
    size_t hit = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      const auto [x, y] = pixel[i];
      ASSERT_EQ(view.primitive.at(x, y), hits[i].primitive) << x << "," << y;
      if (!hits[i].hit()) continue;
      ++hit;
      ASSERT_EQ(view.depth.at(x, y), hits[i].distance) << x << "," << y;  // Bit for bit.
    }
    EXPECT_GT(hit, rays.size() / 2);
  }
}

TEST(ViewRenderer, HoleInWallGivesEmptyPixels) {
  BoxRoom room;
  room.hole = std::make_pair(Eigen::Vector2f(-0.4f, 0.6f), Eigen::Vector2f(0.7f, 1.9f));  // (y, z) ranges.
  Scene scene;
  scene.mesh = room.Build();
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene);
  ASSERT_TRUE(renderer.ok());
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(320, 240, 70);
  const Pose pose{{0.0, 0.1, 1.2}, 5, 3};
  const Eigen::Isometry3d world_from_camera = WorldFromCameraYawPitch(pose.position, pose.yaw, pose.pitch);
  RenderedView view;
  ASSERT_TRUE(renderer->Render(camera, world_from_camera, RenderOptions{kVoxel, 100.0}, &view).ok());
  size_t empty = 0;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const ExactHit e = Trace(room, pose.position, world_from_camera.linear() * camera.PixelRay(x, y));
      if (e.ambiguous) continue;
      ASSERT_EQ(view.hit(x, y), e.hit) << x << "," << y;
      if (e.hit) continue;
      ++empty;
      EXPECT_EQ(view.depth.at(x, y), 0.0f);
      EXPECT_EQ(view.primitive.at(x, y), -1);
      EXPECT_EQ(view.voxel_key.at(x, y), VoxelKey{});
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(view.rgb.at(x, y, k), 0);
        EXPECT_EQ(view.normal.at(x, y, k), 0.0f);
      }
    }
  EXPECT_GT(empty, 5000u);  // The hole fills a good part of the image.
}

TEST(ViewRenderer, MaxDepthLeavesFarPixelsEmpty) {
  BoxRoom room;
  Scene scene;
  scene.mesh = room.Build();
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene);
  ASSERT_TRUE(renderer.ok());
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(64, 48, 60);
  RenderedView view;
  // Looking along +X from x = 0.3: the far wall is 2.187 m away.
  const auto pose = WorldFromCameraYawPitch({0.3, 0.2, 1.3}, 0, 0);
  ASSERT_TRUE(renderer->Render(camera, pose, RenderOptions{kVoxel, 2.0}, &view).ok());
  EXPECT_FALSE(view.hit(32, 24));
  ASSERT_TRUE(renderer->Render(camera, pose, RenderOptions{kVoxel, 2.5}, &view).ok());
  EXPECT_TRUE(view.hit(32, 24));
  EXPECT_NEAR(view.depth.at(32, 24), 2.187, 1e-5);
}

TEST(ViewRenderer, CloudViewShowsPointColours) {
  PointCloud cloud;  // A 2 m x 2 m wall at x = 1, sampled every 2 cm, red.
  for (int i = 0; i <= 100; ++i)
    for (int j = 0; j <= 100; ++j) {
      cloud.points.push_back({1.0f, -1.0f + 0.02f * i, 0.02f * j});
      cloud.colors.push_back({220, 10, 10});
    }
  Scene scene;
  scene.cloud = cloud;
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(64, 48, 40);
  RenderedView view;
  ASSERT_TRUE(renderer->Render(camera, WorldFromCameraYawPitch({0, 0, 1}, 0, 0), RenderOptions{}, &view).ok());
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      ASSERT_TRUE(view.hit(x, y)) << x << "," << y;
      EXPECT_NEAR(view.depth.at(x, y), 1.0f, 2e-3f);
      EXPECT_EQ(view.rgb.at(x, y, 0), 220);
      EXPECT_NEAR(std::abs(view.normal.at(x, y, 0)), 1.0f, 1e-3f);
      EXPECT_EQ(view.voxel_key.at(x, y).x, CoordToKeyIndex(1.0, 0.05));
    }
}

TEST(Camera, YawPitchConventions) {
  const Eigen::Isometry3d t = WorldFromCameraYawPitch({1, 2, 3}, 90, 0);
  EXPECT_TRUE((t.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));   // Forward.
  EXPECT_TRUE((t.linear() * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitZ(), 1e-12));  // Down.
  EXPECT_TRUE((t.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitX(), 1e-12));   // Right.
  EXPECT_NEAR(t.linear().determinant(), 1.0, 1e-12);
  EXPECT_TRUE(t.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  const Eigen::Isometry3d up = WorldFromCameraYawPitch({0, 0, 0}, 0, 30);
  EXPECT_NEAR((up.linear() * Eigen::Vector3d::UnitZ()).z(), 0.5, 1e-12);
  const PinholeCamera c = PinholeCamera::FromHorizontalFov(640, 480, 90);
  EXPECT_DOUBLE_EQ(c.fx, 320.0);
  EXPECT_NEAR(c.HorizontalFovDeg(), 90.0, 1e-9);
  EXPECT_NEAR(c.VerticalFovDeg(), 2 * std::atan(0.75) * 180 / M_PI, 1e-9);
}

TEST(ViewRenderer, RejectsBadCameraAndOptions) {
  BoxRoom room;
  Scene scene;
  scene.mesh = room.Build();
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene);
  ASSERT_TRUE(renderer.ok());
  RenderedView view;
  PinholeCamera bad = PinholeCamera::FromHorizontalFov(64, 48, 60);
  bad.fx = 0;
  Status st = renderer->Render(bad, Eigen::Isometry3d::Identity(), RenderOptions{}, &view);
  EXPECT_EQ(st.code(), StatusCode::kInvalidInput);
  EXPECT_NE(st.message().find("fx"), std::string::npos) << st.message();
  st = renderer->Render(PinholeCamera::FromHorizontalFov(64, 48, 60), Eigen::Isometry3d::Identity(),
                        RenderOptions{0.0, 10.0}, &view);
  EXPECT_NE(st.message().find("voxel_size_m = 0"), std::string::npos) << st.message();
}

}  // namespace
}  // namespace semvox
