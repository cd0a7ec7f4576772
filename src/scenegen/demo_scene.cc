#include "scenegen/demo_scene.h"

#include <algorithm>
#include <cmath>

#include "core/labels.h"

namespace semvox {

void AddWall(MeshBuilder* b, const Eigen::Vector2d& a, const Eigen::Vector2d& c, double thickness, double z0, double z1,
             const std::vector<WallOpening>& openings, Rgb8 color, const FaceTags& tags) {
  const Eigen::Vector2d d = (c - a);
  const double len = d.norm();
  const Eigen::Vector2d u = d / len;
  const double yaw = std::atan2(u.y(), u.x());
  // Build each solid piece as an axis-aligned box in the wall frame, then rotate about its own centre.
  auto piece = [&](double s0, double s1, double zb, double zt) {
    if (s1 - s0 < 1e-6 || zt - zb < 1e-6) return;
    const Eigen::Vector2d mid = a + u * (0.5 * (s0 + s1));
    const double hl = 0.5 * (s1 - s0), ht = 0.5 * thickness;
    b->AddBox(Eigen::Vector3d(mid.x() - hl, mid.y() - ht, zb), Eigen::Vector3d(mid.x() + hl, mid.y() + ht, zt), color,
              tags, yaw);
  };
  std::vector<WallOpening> ops = openings;
  std::sort(ops.begin(), ops.end(), [](const WallOpening& x, const WallOpening& y) { return x.from_m < y.from_m; });
  double s = 0;
  for (const WallOpening& o : ops) {
    piece(s, o.from_m, z0, z1);
    piece(o.from_m, o.to_m, z0, o.bottom_m);  // Sill (windows).
    piece(o.from_m, o.to_m, o.top_m, z1);     // Lintel.
    s = o.to_m;
  }
  piece(s, len, z0, z1);
}

void AddTable(MeshBuilder* b, const Eigen::Vector2d& centre, double sx, double sy, double h, Rgb8 color,
              const FaceTags& tags, double yaw_rad) {
  const double top = 0.04, leg = 0.05;
  const double cs = std::cos(yaw_rad), sn = std::sin(yaw_rad);
  b->AddBox(Eigen::Vector3d(centre.x() - sx / 2, centre.y() - sy / 2, h - top),
            Eigen::Vector3d(centre.x() + sx / 2, centre.y() + sy / 2, h), color, tags, yaw_rad);
  for (int i = 0; i < 4; ++i) {
    const double lx = (i & 1 ? 1 : -1) * (sx / 2 - leg), ly = (i & 2 ? 1 : -1) * (sy / 2 - leg);
    const Eigen::Vector2d p = centre + Eigen::Vector2d(cs * lx - sn * ly, sn * lx + cs * ly);
    b->AddBox(Eigen::Vector3d(p.x() - leg / 2, p.y() - leg / 2, 0.0), Eigen::Vector3d(p.x() + leg / 2, p.y() + leg / 2, h - top),
              color, tags, yaw_rad, true);
  }
}

Mesh BuildDemoApartment() {
  using namespace nyu40;
  MeshBuilder b;
  const double H = 2.6, T = 0.15;
  const Rgb8 wall{236, 232, 222}, floor_wood{164, 118, 76}, tiles{200, 205, 210}, ceiling{248, 248, 248};
  const int kLiving = 1, kBedroom = 2, kBathroom = 3;
  int inst = 0;
  auto tag = [&](int label, int room, bool object = true) { return FaceTags{label, object ? inst++ : -1, room}; };

  // Floors and ceilings per room (x east, y north). Living + kitchen [0,5]x[0,6], bedroom [5,8]x[2.5,6],
  // bathroom [5,8]x[0,2.5].
  struct R { double x0, y0, x1, y1; int room; Rgb8 floor; };
  const R rooms[] = {{0, 0, 5, 6, kLiving, floor_wood}, {5, 2.5, 8, 6, kBedroom, floor_wood}, {5, 0, 8, 2.5, kBathroom, tiles}};
  for (const R& r : rooms) {
    b.AddQuad({r.x0, r.y0, 0}, {r.x1, r.y0, 0}, {r.x1, r.y1, 0}, {r.x0, r.y1, 0}, r.floor, FaceTags{kFloor, -1, r.room});
    b.AddQuad({r.x0, r.y0, H}, {r.x0, r.y1, H}, {r.x1, r.y1, H}, {r.x1, r.y0, H}, ceiling, FaceTags{kCeiling, -1, r.room});
  }
  // Outer walls (centred on the outline, extended by T/2 so corners close) with a living-room window.
  const FaceTags wt{kWall, -1, -1};
  AddWall(&b, {-T / 2, 0}, {8 + T / 2, 0}, T, 0, H, {{1.5, 3.0, 0.9, 2.1}}, wall, wt);
  AddWall(&b, {-T / 2, 6}, {8 + T / 2, 6}, T, 0, H, {{6.0, 7.2, 0.9, 2.1}}, wall, wt);
  AddWall(&b, {0, 0}, {0, 6}, T, 0, H, {}, wall, wt);
  AddWall(&b, {8, 0}, {8, 6}, T, 0, H, {}, wall, wt);
  // Interior walls with doors (0.85 m x 2.05 m).
  AddWall(&b, {5, 0}, {5, 6}, T, 0, H, {{0.8, 1.65, 0, 2.05}, {3.5, 4.35, 0, 2.05}}, wall, wt);
  AddWall(&b, {5, 2.5}, {8, 2.5}, T, 0, H, {}, wall, wt);
  // Window panes set into the openings.
  b.AddBox({1.5, -0.01, 0.9}, {3.0, 0.01, 2.1}, Rgb8{170, 200, 225}, tag(kWindow, kLiving));
  b.AddBox({6.0, 5.99, 0.9}, {7.2, 6.01, 2.1}, Rgb8{170, 200, 225}, tag(kWindow, kBedroom));

  // Living room: sofa, coffee table, TV on a cabinet, bookshelf, picture.
  {
    const FaceTags sofa = tag(kSofa, kLiving);
    b.AddBox({0.6, 4.9, 0}, {2.8, 5.8, 0.45}, Rgb8{70, 90, 140}, sofa, 0, true);
    b.AddBox({0.6, 5.6, 0.45}, {2.8, 5.85, 0.9}, Rgb8{70, 90, 140}, sofa);
    AddTable(&b, {1.7, 4.0}, 1.1, 0.6, 0.42, Rgb8{120, 80, 50}, tag(kTable, kLiving));
    b.AddBox({0.9, 2.4, 0}, {2.5, 2.85, 0.5}, Rgb8{60, 60, 60}, tag(kCabinet, kLiving), 0, true);
    b.AddBox({1.2, 2.6, 0.5}, {2.2, 2.7, 1.1}, Rgb8{20, 20, 25}, tag(kTelevision, kLiving));
    b.AddBox({0.08, 0.6, 0}, {0.45, 1.6, 1.9}, Rgb8{150, 110, 70}, tag(kBookshelf, kLiving), 0, true);
    b.AddBox({0.08, 3.2, 1.3}, {0.1, 4.0, 1.8}, Rgb8{190, 60, 50}, tag(kPicture, kLiving));
    // Kitchen corner: counters with a sink, refrigerator, dining table and chairs.
    const FaceTags counter = tag(kCounter, kLiving);
    b.AddBox({3.0, 5.3, 0}, {4.92, 5.92, 0.9}, Rgb8{230, 230, 225}, counter, 0, true);
    b.AddBox({3.4, 5.45, 0.9}, {3.9, 5.8, 0.95}, Rgb8{190, 190, 195}, tag(kSink, kLiving));
    b.AddBox({4.25, 4.6, 0}, {4.92, 5.25, 1.8}, Rgb8{240, 240, 240}, tag(kRefrigerator, kLiving), 0, true);
    AddTable(&b, {3.7, 3.3}, 1.2, 0.8, 0.75, Rgb8{180, 140, 90}, tag(kTable, kLiving));
    for (int i = 0; i < 2; ++i) {
      const FaceTags chair = tag(kChair, kLiving);
      const double y = i ? 3.95 : 2.65;
      b.AddBox({3.5, y - 0.2, 0.42}, {3.9, y + 0.2, 0.46}, Rgb8{90, 60, 40}, chair);
      b.AddBox({3.5, y - 0.2, 0}, {3.9, y + 0.2, 0.42}, Rgb8{90, 60, 40}, chair, 0, true);
    }
  }
  // Bedroom: bed with pillows, night stand with lamp, wardrobe.
  {
    const FaceTags bed = tag(kBed, kBedroom);
    b.AddBox({5.8, 3.8, 0}, {7.4, 5.92, 0.5}, Rgb8{230, 225, 240}, bed, 0, true);
    b.AddBox({5.8, 5.85, 0}, {7.4, 5.92, 1.0}, Rgb8{110, 80, 60}, bed);
    b.AddBox({6.0, 5.4, 0.5}, {6.5, 5.8, 0.62}, Rgb8{250, 250, 250}, tag(kPillow, kBedroom));
    b.AddBox({6.7, 5.4, 0.5}, {7.2, 5.8, 0.62}, Rgb8{250, 250, 250}, tag(kPillow, kBedroom));
    b.AddBox({7.45, 5.4, 0}, {7.92, 5.9, 0.55}, Rgb8{120, 85, 55}, tag(kNightStand, kBedroom), 0, true);
    b.AddBox({7.6, 5.55, 0.55}, {7.75, 5.7, 0.95}, Rgb8{240, 220, 150}, tag(kLamp, kBedroom));
    b.AddBox({7.3, 2.6, 0}, {7.92, 3.8, 2.0}, Rgb8{200, 190, 170}, tag(kDresser, kBedroom), 0, true);
  }
  // Bathroom: toilet, sink on a cabinet, bathtub, mirror.
  {
    b.AddBox({7.4, 0.3, 0}, {7.92, 0.7, 0.42}, Rgb8{250, 250, 250}, tag(kToilet, kBathroom), 0, true);
    b.AddBox({5.6, 2.0, 0}, {6.3, 2.42, 0.8}, Rgb8{250, 250, 250}, tag(kSink, kBathroom), 0, true);
    b.AddBox({5.7, 2.4, 1.1}, {6.2, 2.42, 1.7}, Rgb8{200, 220, 230}, tag(kMirror, kBathroom));
    b.AddBox({5.9, 0.08, 0}, {7.3, 0.8, 0.55}, Rgb8{245, 245, 250}, tag(kBathtub, kBathroom), 0, true);
  }
  return b.Take();
}

}  // namespace semvox
