// Apartments on a given floor plan (scenegen/plan_apartment.h):
//  - a hand-made L-shaped flat (a living room with an L-shaped floor, a WC behind a door, a toilet): the room
//    ground truth is the plan's raster, walls stand on the wall lines with a gap and a lintel at the door,
//    every wall face is tagged with the room it faces, floors cover the rooms and the door gap, the toilet
//    is an object of the WC; an exterior wall of the living room gets a window;
//  - furniture on that flat: the living room (no fixture) is furnished, every corner of every piece stands
//    on the living room's own floor (no wall, no other room, not the door gap), at least 0.3 m from the door
//    gap's centre; the WC (it has its toilet) gets nothing more; with `furniture = false` the fixtures and
//    windows are the only objects;
//  - a bedroom with a wide door in every wall still gets its bed (FloorPlan::place_defining_furniture), before
//    one door at most; a room too small for a bed gets none;
//  - `semvox generate --plan` on a real R2V plan of ../shared/data/r2v (skipped when absent): the files
//    of a generated apartment, with one room per closed region of the plan; bad plans rejected with one
//    error line and nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sys/wait.h>

#include "core/labels.h"
#include "scenegen/apartment_io.h"
#include "scenegen/plan_apartment.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

namespace fs = std::filesystem;

// L-shaped living room (id 1): [0, 4] x [0, 2] plus [0, 2] x [2, 4]; WC (id 2): [2.1, 4] x [2.1, 4] minus
// nothing; wall lines on x = 0, 4, 2.05 (from y = 2.05 to 4), y = 0, 4, 2.05 (from x = 2.05 to 4); the
// door from the living room to the WC in the wall y = 2.05 at x in [2.6, 3.4]; a toilet in the WC.
PlanLayout LShapedFlat() {
  PlanLayout l;
  l.resolution_m = 0.05;
  l.origin = Eigen::Vector2d(-0.5, -0.5);
  const int n = 100;  // 5 m.
  l.rooms = ImageU16(n, n, 1, 0);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const double x = l.origin.x() + (c + 0.5) * l.resolution_m, y = l.origin.y() + (r + 0.5) * l.resolution_m;
      if (x < 0.05 || x > 3.95 || y < 0.05 || y > 3.95) continue;  // Exterior walls and outside.
      const bool wc = x > 2.1 && y > 2.1;
      const bool wall = (std::fabs(x - 2.05) < 0.05 && y > 2.0) || (std::fabs(y - 2.05) < 0.05 && x > 2.0);
      if (!wall) l.rooms.at(c, r) = wc ? 2 : 1;
    }
  const auto seg = [](double x0, double y0, double x1, double y1) { return PlanLayout::Segment{{x0, y0}, {x1, y1}}; };
  l.walls = {seg(0, 0, 4, 0), seg(4, 0, 4, 4), seg(4, 4, 0, 4), seg(0, 4, 0, 0), seg(2.05, 2.05, 2.05, 4), seg(2.05, 2.05, 4, 2.05)};
  l.doors = {seg(2.6, 2.05, 3.4, 2.05)};
  l.fixtures = {{{3.3, 3.4}, {3.8, 3.9}, nyu40::kToilet}};
  l.room_type = {0, RoomTypeIdByName("living_room"), RoomTypeIdByName("bathroom")};
  return l;
}

bool InsideBox(const OrientedBox& b, const Eigen::Vector3d& p) {
  const double c = std::cos(b.yaw_rad), s = std::sin(b.yaw_rad);
  const Eigen::Vector3d q = p - b.center;
  const double lx = c * q.x() + s * q.y(), ly = -s * q.x() + c * q.y();
  return std::fabs(lx) <= b.size.x() / 2 && std::fabs(ly) <= b.size.y() / 2 && std::fabs(q.z()) <= b.size.z() / 2;
}

// The four corners of a box's footprint (x, y).
std::array<Eigen::Vector2d, 4> FootprintCorners(const OrientedBox& b) {
  const double c = std::cos(b.yaw_rad), s = std::sin(b.yaw_rad);
  std::array<Eigen::Vector2d, 4> out;
  for (int corner = 0; corner < 4; ++corner) {
    const double lx = (corner & 1 ? 0.5 : -0.5) * b.size.x(), ly = (corner & 2 ? 0.5 : -0.5) * b.size.y();
    out[size_t(corner)] = Eigen::Vector2d(b.center.x() + c * lx - s * ly, b.center.y() + s * lx + c * ly);
  }
  return out;
}

TEST(PlanApartment, LShapedFlatHasItsRoomsWallsDoorGapAndFixture) {
  const PlanLayout layout = LShapedFlat();
  Result<Apartment> apt = ApartmentFromLayout(layout, PlanApartmentOptions{});
  ASSERT_TRUE(apt.ok()) << apt.status().message();
  ASSERT_EQ(apt->rooms.size(), 2u);
  // Room ground truth from the raster: the L shape's area (3.9 x 1.95 + 1.95 x 1.9, to the pixel) and its box.
  const RoomGt& living = apt->rooms[0];
  EXPECT_NEAR(living.area_m2(), 3.9 * 2.0 + 2.0 * 1.9, 0.3);
  EXPECT_NEAR(living.x1 - living.x0, 3.9, 0.06);
  EXPECT_EQ(RoomIdAt(*apt, 1.0, 3.0), 1) << "the L's arm is the living room";
  EXPECT_EQ(RoomIdAt(*apt, 3.0, 3.0), 2);
  EXPECT_EQ(RoomIdAt(*apt, 3.0, 1.0), 1);
  EXPECT_EQ(apt->rooms[1].type_id, RoomTypeIdByName("bathroom"));
  // Walls: a gap at the door up to the door height, a lintel above it; solid wall beside the door.
  auto wall_at = [&](double x, double y, double z) {
    for (const SolidPart& p : apt->parts)
      if (p.structural && InsideBox(p.box, {x, y, z})) return true;
    return false;
  };
  EXPECT_FALSE(wall_at(3.0, 2.05, 1.0)) << "door gap";
  EXPECT_TRUE(wall_at(3.0, 2.05, 2.2)) << "lintel";
  EXPECT_TRUE(wall_at(2.3, 2.05, 1.0));
  EXPECT_TRUE(wall_at(0.0, 1.0, 1.0));
  EXPECT_FALSE(wall_at(1.0, 3.0, 1.0)) << "no wall across the L";
  // Faces: every wall face looks into the room it is tagged with (or out of the flat, tagged -1); floors cover
  // the rooms and the door gap; a toilet object in the WC.
  const auto& lab = apt->mesh.face_attributes.at("label");
  const auto& room = apt->mesh.face_attributes.at("room");
  int wall_faces = 0, wall_ok = 0, floor_gap = 0, toilet_faces = 0;
  for (size_t f = 0; f < apt->mesh.faces.size(); ++f) {
    const auto& t = apt->mesh.faces[f];
    const Eigen::Vector3d a = apt->mesh.vertices[size_t(t[0])].cast<double>(), b = apt->mesh.vertices[size_t(t[1])].cast<double>(),
                          c = apt->mesh.vertices[size_t(t[2])].cast<double>();
    const Eigen::Vector3d centre = (a + b + c) / 3, normal = (b - a).cross(c - a).normalized();
    if (lab[f] == nyu40::kWall && std::fabs(normal.z()) < 0.1) {
      const Eigen::Vector3d q = centre + 0.1 * normal;
      const int seen = RoomIdAt(*apt, q.x(), q.y());
      ++wall_faces;
      wall_ok += room[f] == (seen > 0 ? seen : -1);
    }
    if (lab[f] == nyu40::kFloor && std::fabs(centre.y() - 2.05) < 0.05 && centre.x() > 2.7 && centre.x() < 3.3) ++floor_gap;
    if (lab[f] == nyu40::kToilet) {
      ++toilet_faces;
      EXPECT_EQ(room[f], 2);
    }
  }
  ASSERT_GT(wall_faces, 50);
  EXPECT_GE(double(wall_ok) / wall_faces, 0.95) << wall_ok << " of " << wall_faces;
  EXPECT_GT(floor_gap, 0) << "floor under the door gap";
  EXPECT_GE(toilet_faces, 5);
  ASSERT_EQ(apt->doors.size(), 1u);
  EXPECT_EQ(std::set<int>({apt->doors[0].room_a, apt->doors[0].room_b}), std::set<int>({1, 2}));
  // Windows go into exterior walls of rooms that have them: not into the WC, nowhere inside the flat.
  for (const WindowGt& w : apt->windows) {
    EXPECT_EQ(w.room, 1);
    EXPECT_TRUE(std::fabs(w.center.x()) < 0.01 || std::fabs(w.center.x() - 4) < 0.01 || std::fabs(w.center.y()) < 0.01 ||
                std::fabs(w.center.y() - 4) < 0.01);
  }
  // The ground-truth raster written for `semvox eval` is the plan's.
  const FloorGrid g = MakeFloorGrid(*apt, GroundTruthOptions());
  const ImageU16 gt = RasterizeRooms(*apt, g);
  int px[3] = {0, 0, 0};
  for (uint16_t v : gt.data) ++px[std::min<int>(v, 2)];
  EXPECT_NEAR(px[1] * g.resolution * g.resolution, living.area_m2(), 0.1);
  EXPECT_NEAR(px[2] * g.resolution * g.resolution, apt->rooms[1].area_m2(), 0.1);
}

TEST(PlanApartment, FurnitureStandsOnItsRoomsFloorClearOfWallsAndDoors) {
  const PlanLayout layout = LShapedFlat();
  PlanApartmentOptions options;
  for (uint64_t seed = 0; seed < 4; ++seed) {
    options.seed = seed;
    Result<Apartment> apt = ApartmentFromLayout(layout, options);
    ASSERT_TRUE(apt.ok()) << apt.status().message();
    int living = 0;
    for (const ObjectGt& o : apt->objects) {
      if (o.label == nyu40::kWindow || o.label == nyu40::kToilet) continue;
      EXPECT_EQ(o.room, 1) << "seed " << seed << ": a " << o.label << " outside the living room";
      ++living;
      for (const Eigen::Vector2d& p : FootprintCorners(o.box)) {
        EXPECT_EQ(RoomIdAt(*apt, p.x(), p.y()), 1) << "seed " << seed << ": object " << o.label << " corner " << p.transpose();
        EXPECT_GT(std::hypot(p.x() - 3.0, p.y() - 2.05), 0.3) << "seed " << seed << ": object " << o.label << " in the door gap";
      }
    }
    EXPECT_GE(living, 2) << "seed " << seed << ": the living room is furnished";
  }
  options.furniture = false;
  Result<Apartment> bare = ApartmentFromLayout(layout, options);
  ASSERT_TRUE(bare.ok());
  for (const ObjectGt& o : bare->objects) EXPECT_TRUE(o.label == nyu40::kWindow || o.label == nyu40::kToilet) << o.label;
}

// One bedroom [0, w] x [0, h] (walls on its edges) with a door gap `door` metres wide in the middle of every
// wall, leading out (a Japanese room with sliding doors to closets, corridor and balcony).
PlanLayout BedroomWithADoorOnEveryWall(double w, double h, double door) {
  PlanLayout l;
  l.resolution_m = 0.05;
  l.origin = Eigen::Vector2d(-0.5, -0.5);
  const int nx = int((w + 1) / l.resolution_m), ny = int((h + 1) / l.resolution_m);
  l.rooms = ImageU16(nx, ny, 1, 0);
  for (int r = 0; r < ny; ++r)
    for (int c = 0; c < nx; ++c) {
      const double x = l.origin.x() + (c + 0.5) * l.resolution_m, y = l.origin.y() + (r + 0.5) * l.resolution_m;
      if (x > 0.05 && x < w - 0.05 && y > 0.05 && y < h - 0.05) l.rooms.at(c, r) = 1;
    }
  const auto seg = [](double x0, double y0, double x1, double y1) { return PlanLayout::Segment{{x0, y0}, {x1, y1}}; };
  l.walls = {seg(0, 0, w, 0), seg(w, 0, w, h), seg(w, h, 0, h), seg(0, h, 0, 0)};
  l.doors = {seg(w / 2 - door / 2, 0, w / 2 + door / 2, 0), seg(w / 2 - door / 2, h, w / 2 + door / 2, h),
             seg(0, h / 2 - door / 2, 0, h / 2 + door / 2), seg(w, h / 2 - door / 2, w, h / 2 + door / 2)};
  l.room_type = {0, RoomTypeIdByName("bedroom")};
  return l;
}

TEST(PlanApartment, BedroomGetsItsBedWhenOneFitsBeforeTheFewestDoors) {
  // 3.2 x 2.7 m with a 1.6 m door in every wall: no spot against a wall keeps every door's swing square or
  // passage clear, so the bed stands before exactly one door (the fewest possible); every seed gets one.
  const PlanLayout layout = BedroomWithADoorOnEveryWall(3.2, 2.7, 1.6);
  PlanApartmentOptions options;
  for (uint64_t seed = 0; seed < 6; ++seed) {
    options.seed = seed;
    Result<Apartment> apt = ApartmentFromLayout(layout, options);
    ASSERT_TRUE(apt.ok()) << apt.status().message();
    int beds = 0;
    for (const ObjectGt& o : apt->objects) {
      if (o.label != nyu40::kBed) continue;
      ++beds;
      EXPECT_EQ(o.room, 1);
      for (const Eigen::Vector2d& p : FootprintCorners(o.box)) EXPECT_EQ(RoomIdAt(*apt, p.x(), p.y()), 1) << "seed " << seed;
      // Doors whose passage (points across the gap, 0.2 m inside the room) the bed covers.
      int blocked = 0;
      for (int door = 0; door < 4; ++door) {
        bool covered = false;
        for (int k = 0; k <= 8; ++k) {
          const double t = -0.8 + 0.2 * k;  // Across the 1.6 m gap.
          const Eigen::Vector3d p = door == 0 ? Eigen::Vector3d(1.6 + t, 0.2, 0.2) : door == 1 ? Eigen::Vector3d(1.6 + t, 2.5, 0.2)
                                  : door == 2 ? Eigen::Vector3d(0.2, 1.35 + t, 0.2) : Eigen::Vector3d(3.0, 1.35 + t, 0.2);
          covered = covered || InsideBox(o.box, p);
        }
        blocked += covered;
      }
      EXPECT_EQ(blocked, 1) << "seed " << seed << ": the bed stands before " << blocked << " doors";
    }
    EXPECT_EQ(beds, 1) << "seed " << seed;
  }
  // A room too small for any bed (1.7 x 1.8 m) gets none, and the apartment is still built.
  Result<Apartment> small = ApartmentFromLayout(BedroomWithADoorOnEveryWall(1.7, 1.8, 0.7), options);
  ASSERT_TRUE(small.ok()) << small.status().message();
  for (const ObjectGt& o : small->objects) EXPECT_NE(o.label, nyu40::kBed);
}

TEST(PlanApartment, RegionsTooSmallToEnterAreNoRooms) {
  // A 0.3 m x 0.4 m shaft (id 3) in the living room's corner: no room, and the rooms keep ids 1 and 2.
  PlanLayout layout = LShapedFlat();
  for (int r = 0; r < layout.rooms.height; ++r)
    for (int c = 0; c < layout.rooms.width; ++c) {
      const double x = layout.origin.x() + (c + 0.5) * layout.resolution_m, y = layout.origin.y() + (r + 0.5) * layout.resolution_m;
      if (x > 0.1 && x < 0.4 && y > 0.1 && y < 0.5) layout.rooms.at(c, r) = 3;
    }
  layout.room_type.push_back(RoomTypeIdByName("storage"));
  Result<Apartment> apt = ApartmentFromLayout(layout, PlanApartmentOptions{});
  ASSERT_TRUE(apt.ok()) << apt.status().message();
  ASSERT_EQ(apt->rooms.size(), 2u);
  EXPECT_EQ(RoomIdAt(*apt, 0.25, 0.3), 0);
  EXPECT_EQ(RoomIdAt(*apt, 3.0, 3.0), 2);
  PlanApartmentOptions all;
  all.min_room_area_m2 = 0;
  EXPECT_EQ(ApartmentFromLayout(layout, all)->rooms.size(), 3u);
}

TEST(PlanApartment, RejectsLayoutsWithoutRoomsAndBadOptions) {
  PlanLayout empty = LShapedFlat();
  std::fill(empty.rooms.data.begin(), empty.rooms.data.end(), 0);
  Result<Apartment> a = ApartmentFromLayout(empty, PlanApartmentOptions{});
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.status().message().find("no closed room"), std::string::npos) << a.status().message();
  PlanApartmentOptions o;
  o.door_height_m = 3.0;
  EXPECT_FALSE(ApartmentFromLayout(LShapedFlat(), o).ok());
}

int RunSemvox(const std::string& args, const std::string& log) {
  const int st = std::system((std::string(SEMVOX_BINARY) + " " + args + " >" + log + " 2>&1").c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

TEST(GenerateCommand, PlanBuildsARealLayoutAndRejectsBadPlans) {
  using testing::ReadText;
  const std::string plan = std::string(SEMVOX_SOURCE_DIR) + "/../shared/data/r2v/plan_0300.txt";
  if (!fs::exists(SEMVOX_BINARY)) GTEST_SKIP() << "semvox binary not built";
  const testing::ScratchDir dir("plan_cli");
  const std::string log = dir.File("log.txt");
  // Bad plans: one error line naming the file, exit 2, no output directory.
  testing::WriteText(dir.File("not_a_plan.txt"), "hello world\n");
  testing::WriteText(dir.File("no_door.txt"), "0 0 100 0 wall 1 1\n100 0 100 100 wall 1 1\n10 10 40 30 bedroom 1 1\n");
  for (const char* bad : {"not_a_plan.txt", "no_door.txt", "missing.txt"}) {
    EXPECT_EQ(RunSemvox("generate --plan " + dir.File(bad) + " -o " + dir.File("out_bad"), log), 2) << bad;
    const std::string text = ReadText(log);
    EXPECT_NE(text.find(bad), std::string::npos) << text;
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
    EXPECT_FALSE(fs::exists(dir.File("out_bad"))) << bad;
  }
  if (!fs::exists(plan)) GTEST_SKIP() << "no R2V plans in ../shared/data/r2v";
  ASSERT_EQ(RunSemvox("generate --plan " + plan + " --seed 3 -o " + dir.File("a"), log), 0) << ReadText(log);
  ASSERT_EQ(RunSemvox("generate --plan " + plan + " --seed 3 -o " + dir.File("b"), log), 0) << ReadText(log);
  for (const char* name : {"mesh.ply", "gt_mesh.ply", "gt.json", "rooms_gt.png", "topview_gt.png"}) {
    const std::string a = ReadText(dir.File(std::string("a/") + name));
    EXPECT_FALSE(a.empty()) << name;
    EXPECT_EQ(a, ReadText(dir.File(std::string("b/") + name))) << name << ": same plan and seed, same bytes";
  }
  const std::string gt = ReadText(dir.File("a/gt.json"));
  EXPECT_NE(gt.find("\"plan\": \"" + plan + "\""), std::string::npos);
  // plan_0300: 11 closed regions, 3 of them pipe shafts under 0.5 m² that are no rooms: 8 rooms.
  EXPECT_NE(gt.find("\"rooms\": 8"), std::string::npos) << gt.substr(gt.find("\"counts\""), 200);
}

}  // namespace
}  // namespace semvox
