// The apartment generator: determinism, plausible dimensions, no interpenetration, reachability.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include "core/file_util.h"
#include "core/labels.h"
#include "scenegen/apartment.h"
#include "scenegen/apartment_io.h"
#include "scenegen/layout.h"
#include "scenegen/scan_artefacts.h"

namespace semvox {
namespace {

namespace fs = std::filesystem;

Apartment Generate(uint64_t seed, bool shape_variety = false) {
  ApartmentOptions o;
  o.seed = seed;
  o.shape_variety = shape_variety;
  Result<Apartment> a = GenerateApartment(o);
  EXPECT_TRUE(a.ok()) << a.status().message();
  return std::move(a).value();
}

std::string Slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream os;
  os << f.rdbuf();
  return os.str();
}

fs::path TempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("semvox_scenegen_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

// Two oriented boxes (yaw about z only) overlap with positive volume after shrinking each by `shrink`.
bool BoxesIntersect(const OrientedBox& a, const OrientedBox& b, double shrink) {
  const double az0 = a.center.z() - a.size.z() / 2 + shrink, az1 = a.center.z() + a.size.z() / 2 - shrink;
  const double bz0 = b.center.z() - b.size.z() / 2 + shrink, bz1 = b.center.z() + b.size.z() / 2 - shrink;
  if (az1 <= bz0 || bz1 <= az0) return false;
  const Eigen::Vector2d axes[4] = {{std::cos(a.yaw_rad), std::sin(a.yaw_rad)}, {-std::sin(a.yaw_rad), std::cos(a.yaw_rad)},
                                   {std::cos(b.yaw_rad), std::sin(b.yaw_rad)}, {-std::sin(b.yaw_rad), std::cos(b.yaw_rad)}};
  const Eigen::Vector2d d = (b.center - a.center).head<2>();
  const double ahx = a.size.x() / 2 - shrink, ahy = a.size.y() / 2 - shrink, bhx = b.size.x() / 2 - shrink, bhy = b.size.y() / 2 - shrink;
  for (const Eigen::Vector2d& n : axes) {
    const double ra = ahx * std::fabs(axes[0].dot(n)) + ahy * std::fabs(axes[1].dot(n));
    const double rb = bhx * std::fabs(axes[2].dot(n)) + bhy * std::fabs(axes[3].dot(n));
    if (std::fabs(d.dot(n)) >= ra + rb) return false;
  }
  return true;
}

constexpr int kSeeds = 40;

TEST(ApartmentGenerator, SameSeedGivesSameBytes) {
  ApartmentOptions options;
  options.seed = 12345;
  ScanArtefactOptions artefacts;
  artefacts.seed = options.seed;
  const fs::path a = TempDir("a"), b = TempDir("b");
  for (const fs::path& d : {a, b}) {
    Result<Apartment> apt = GenerateApartment(options);
    ASSERT_TRUE(apt.ok());
    ASSERT_TRUE(WriteApartment(d.string(), *apt, options, artefacts, GroundTruthOptions(), false).ok());
  }
  for (const char* name : {"mesh.ply", "gt_mesh.ply", "gt.json", "rooms_gt.png", "topview_gt.png", "preview.png"}) {
    const std::string x = Slurp(a / name), y = Slurp(b / name);
    EXPECT_FALSE(x.empty()) << name;
    EXPECT_EQ(x, y) << name << " differs between two runs with the same seed";
  }
  // A different seed gives a different apartment.
  options.seed = 12346;
  Result<Apartment> other = GenerateApartment(options);
  ASSERT_TRUE(other.ok());
  EXPECT_NE(other->mesh.faces.size() * 1000 + other->objects.size(), Generate(12345).mesh.faces.size() * 1000 + Generate(12345).objects.size());
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(ApartmentGenerator, DimensionsAreRealistic) {
  const scenegen::RoomTypeIds& t = scenegen::RoomTypeIds::Get();
  std::set<int> room_counts;
  bool saw_corridor = false, saw_open_plan = false, saw_studio_size = false;
  for (int seed = 0; seed < kSeeds; ++seed) {
    const Apartment apt = Generate(uint64_t(seed));
    ASSERT_GE(apt.rooms.size(), 1u);
    ASSERT_LE(apt.rooms.size(), 8u);
    room_counts.insert(int(apt.rooms.size()));
    const double ceiling = apt.ceiling_z_m - apt.floor_z_m;
    EXPECT_GE(ceiling, 2.3 - 1e-9);
    EXPECT_LE(ceiling, 2.9 + 1e-9);
    EXPECT_GE(apt.interior_wall_m, 0.1 - 1e-9);
    EXPECT_LE(apt.exterior_wall_m, 0.25 + 1e-9);
    for (const RoomGt& r : apt.rooms) {
      EXPECT_GE(r.area_m2(), 3.0) << "seed " << seed << " room " << r.id;
      EXPECT_LE(r.area_m2(), 35.0) << "seed " << seed << " room " << r.id;
      saw_corridor |= r.type_id == t.corridor;
      saw_open_plan |= !r.open_to.empty();
      saw_studio_size |= apt.rooms.size() == 1;
    }
    for (const DoorGt& d : apt.doors) {
      EXPECT_GE(d.width_m, 0.8 - 1e-9);
      EXPECT_LE(d.width_m, 0.9 + 1e-9);
      EXPECT_GE(d.height_m, 2.0 - 1e-9);
      EXPECT_LE(d.height_m, 2.1 + 1e-9);
    }
    int entrances = 0;
    for (const DoorGt& d : apt.doors) entrances += d.room_b < 0;
    EXPECT_EQ(entrances, 1) << "seed " << seed;
  }
  EXPECT_GE(room_counts.size(), 6u) << "room counts should span most of 1-8";
  EXPECT_TRUE(saw_corridor);
  EXPECT_TRUE(saw_open_plan);
  EXPECT_TRUE(saw_studio_size);
}

void ExpectNothingIntersects(const Apartment& apt, int seed) {
  {
    const auto& parts = apt.parts;
    for (size_t i = 0; i < parts.size(); ++i) {
      if (parts[i].structural || parts[i].label == nyu40::kFloorMat) continue;  // Rugs lie under furniture by design.
      for (size_t j = 0; j < parts.size(); ++j) {
        if (j == i || parts[j].label == nyu40::kFloorMat) continue;
        if (!parts[j].structural && (j < i || parts[j].instance == parts[i].instance)) continue;
        EXPECT_FALSE(BoxesIntersect(parts[i].box, parts[j].box, 1e-3))
            << "seed " << seed << ": " << Nyu40Labels()[size_t(parts[i].label)].name << " (instance " << parts[i].instance
            << ") intersects " << (parts[j].structural ? "a wall" : Nyu40Labels()[size_t(parts[j].label)].name);
      }
    }
    // Every object stays inside the clear interior of its room (walls are never pierced).
    for (const ObjectGt& o : apt.objects) {
      if (o.label == nyu40::kDoor || o.label == nyu40::kWindow) continue;
      const RoomGt& r = apt.rooms[size_t(o.room - 1)];
      const double c = std::fabs(std::cos(o.box.yaw_rad)), s = std::fabs(std::sin(o.box.yaw_rad));
      const double ex = o.box.size.x() / 2 * c + o.box.size.y() / 2 * s, ey = o.box.size.x() / 2 * s + o.box.size.y() / 2 * c;
      EXPECT_GE(o.box.center.x() - ex, r.x0 - 1e-6) << "seed " << seed << " instance " << o.instance;
      EXPECT_LE(o.box.center.x() + ex, r.x1 + 1e-6) << "seed " << seed << " instance " << o.instance;
      EXPECT_GE(o.box.center.y() - ey, r.y0 - 1e-6) << "seed " << seed << " instance " << o.instance;
      EXPECT_LE(o.box.center.y() + ey, r.y1 + 1e-6) << "seed " << seed << " instance " << o.instance;
      EXPECT_LE(o.box.center.z() + o.box.size.z() / 2, apt.ceiling_z_m + 1e-6) << "seed " << seed;
    }
  }
}

TEST(ApartmentGenerator, NoFurnitureIntersectsWallsOrOtherFurniture) {
  for (int seed = 0; seed < kSeeds; ++seed) ExpectNothingIntersects(Generate(uint64_t(seed)), seed);
}

// Flood fill on a 5 cm grid at knee height (below every window sill) from the first room; walls block,
// and with `furniture` so does every piece of furniture standing there. Returns the rooms reached.
std::set<int> ReachableRooms(const Apartment& apt, bool furniture) {
  GroundTruthOptions go;
  const FloorGrid g = MakeFloorGrid(apt, go);
  const ImageU16 rooms = RasterizeRooms(apt, g);
  const double z = apt.floor_z_m + 0.5;
  // Walkable: inside a room's interior grown by the exterior wall thickness (covers every wall and door
  // opening, never the outside), and not inside a blocking solid.
  std::vector<uint8_t> free(size_t(g.width) * g.height, 0);
  for (int r = 0; r < g.height; ++r)
    for (int c = 0; c < g.width; ++c) {
      const double x = g.CenterX(c), y = g.CenterY(r);
      bool inside = false;
      for (const RoomGt& room : apt.rooms) {
        const double m = apt.exterior_wall_m / 2 - 1e-3;
        inside |= x > room.x0 - m && x < room.x1 + m && y > room.y0 - m && y < room.y1 + m;
      }
      if (!inside) continue;
      bool blocked = false;
      for (const SolidPart& p : apt.parts) {
        if (!(p.structural || (furniture && p.label != nyu40::kDoor && p.label != nyu40::kFloorMat))) continue;
        const OrientedBox& b = p.box;
        if (std::fabs(z - b.center.z()) > b.size.z() / 2) continue;
        const double cs = std::cos(b.yaw_rad), sn = std::sin(b.yaw_rad), dx = x - b.center.x(), dy = y - b.center.y();
        if (std::fabs(cs * dx + sn * dy) <= b.size.x() / 2 && std::fabs(-sn * dx + cs * dy) <= b.size.y() / 2) {
          blocked = true;
          break;
        }
      }
      free[size_t(r) * g.width + c] = !blocked;
    }
  std::deque<int> queue;
  std::vector<uint8_t> seen(free.size(), 0);
  // Seeds: every free pixel of room 1 (furniture may wall off a pocket of it; doors must still connect).
  for (size_t i = 0; i < free.size(); ++i)
    if (free[i] && rooms.data[i] == 1) queue.push_back(int(i)), seen[i] = 1;
  std::set<int> reached;
  while (!queue.empty()) {
    const int i = queue.front();
    queue.pop_front();
    if (rooms.data[size_t(i)]) reached.insert(rooms.data[size_t(i)]);
    const int c = i % g.width, r = i / g.width;
    const int nb[4][2] = {{c + 1, r}, {c - 1, r}, {c, r + 1}, {c, r - 1}};
    for (const auto& n : nb) {
      if (n[0] < 0 || n[1] < 0 || n[0] >= g.width || n[1] >= g.height) continue;
      const size_t j = size_t(n[1]) * g.width + n[0];
      if (free[j] && !seen[j]) seen[j] = 1, queue.push_back(int(j));
    }
  }
  return reached;
}

TEST(ApartmentGenerator, EveryRoomReachableThroughDoors) {
  for (int seed = 0; seed < kSeeds; ++seed) {
    const Apartment apt = Generate(uint64_t(seed));
    EXPECT_EQ(ReachableRooms(apt, false).size(), apt.rooms.size()) << "seed " << seed << ": walls cut a room off";
    EXPECT_EQ(ReachableRooms(apt, true).size(), apt.rooms.size()) << "seed " << seed << ": furniture blocks a door";
  }
}

// Shape variety (the randomised training and validation scans): corner sofas (a chaise makes the sofa
// 1.45 m deep or more; plain sofas are at most 0.95 m), bar tables (0.9 m high or more; dining and coffee
// tables are at most 0.77 m), waste bins (otherfurniture under 0.75 m with a footprint under 0.5 x 0.5 m;
// the generator's other otherfurniture, wardrobes and washers, is larger), none of them without it; still
// nothing intersects and every room is reachable.
TEST(ApartmentGenerator, ShapeVarietyAddsCornerSofasBarTablesAndBins) {
  auto count = [](const Apartment& apt, int* corner_sofas, int* bar_tables, int* bins) {
    for (const ObjectGt& o : apt.objects) {
      const Eigen::Vector3d& s = o.box.size;
      if (o.label == nyu40::kSofa && std::min(s.x(), s.y()) >= 1.44) ++*corner_sofas;
      if (o.label == nyu40::kTable && s.z() >= 0.89) ++*bar_tables;
      if (o.label == nyu40::kOtherFurniture && s.z() <= 0.75 && s.x() <= 0.5 && s.y() <= 0.5) ++*bins;
    }
  };
  int with[3] = {0, 0, 0}, without[3] = {0, 0, 0};
  for (int seed = 0; seed < kSeeds; ++seed) {
    const Apartment varied = Generate(uint64_t(seed), true);
    count(varied, &with[0], &with[1], &with[2]);
    count(Generate(uint64_t(seed)), &without[0], &without[1], &without[2]);
    ExpectNothingIntersects(varied, seed);
    const std::set<int> reached = ReachableRooms(varied, true);
    EXPECT_EQ(reached.size(), varied.rooms.size()) << "seed " << seed;
  }
  EXPECT_GE(with[0], 3);
  EXPECT_GE(with[1], 3);
  EXPECT_GE(with[2], 10);
  EXPECT_EQ(without[0], 0);
  EXPECT_EQ(without[1], 0);
  EXPECT_EQ(without[2], 0);
}

// count(apartment) summed over the kSeeds apartments with shape variety, and over the same seeds without it.
template <class Count>
std::pair<int, int> CountVariedAndPlain(const Count& count) {
  int varied = 0, plain = 0;
  for (int seed = 0; seed < kSeeds; ++seed) {
    varied += count(Generate(uint64_t(seed), true));
    plain += count(Generate(uint64_t(seed)));
  }
  return {varied, plain};
}

// Upholstered sofas (shape variety): wide, high arms and deep back cushions, seen from above as a broad band at
// 0.55-0.75 m around the seat; the plain generator's arms are 0.15 m wide and its back cushions 0.14 m deep.
TEST(ApartmentGenerator, ShapeVarietyAddsUpholsteredSofas) {
  auto upholstered = [](const Apartment& apt) {
    std::set<int> sofas;
    for (const SolidPart& p : apt.parts) {
      if (p.structural || p.label != nyu40::kSofa) continue;
      const double top = p.box.center.z() + p.box.size.z() / 2 - apt.floor_z_m;
      if (top >= 0.55 && top <= 0.75 && std::min(p.box.size.x(), p.box.size.y()) >= 0.2) sofas.insert(p.instance);
    }
    return int(sofas.size());
  };
  const auto [with, without] = CountVariedAndPlain(upholstered);
  EXPECT_GE(with, 3) << "upholstered sofas in " << kSeeds << " varied apartments";
  EXPECT_EQ(without, 0);
  std::printf("upholstered sofas: %d with shape variety, %d without\n", with, without);
}

// Sectionals (shape variety): a corner sofa whose back runs on along the chaise's outer side, so that its
// backs form an L (the ScanNet studio's sofa), seen as two back-high parts (0.77 m or more, at most 0.31 m
// deep) at right angles; a plain corner sofa has one back and the plain generator none of either.
TEST(ApartmentGenerator, ShapeVarietyAddsSectionalSofas) {
  auto sectionals = [](const Apartment& apt) {
    std::map<int, std::vector<bool>> backs;  // Per sofa: whether each back runs along x.
    for (const SolidPart& p : apt.parts) {
      if (p.structural || p.label != nyu40::kSofa) continue;
      const Eigen::Vector3d& s = p.box.size;
      const double top = p.box.center.z() + s.z() / 2 - apt.floor_z_m;
      if (top >= 0.77 && std::min(s.x(), s.y()) <= 0.31 && std::max(s.x(), s.y()) >= 0.6) backs[p.instance].push_back(s.x() > s.y());
    }
    int n = 0;
    for (const auto& [instance, along_x] : backs)
      n += std::count(along_x.begin(), along_x.end(), true) > 0 && std::count(along_x.begin(), along_x.end(), false) > 0;
    return n;
  };
  const auto [with, without] = CountVariedAndPlain(sectionals);
  EXPECT_GE(with, 2) << "sectional sofas in " << kSeeds << " varied apartments";
  EXPECT_EQ(without, 0);
  std::printf("sectional sofas: %d with shape variety, %d without\n", with, without);
}

// Toilets (shape variety): hung on the wall (no part on the floor) or a bowl over a narrower pedestal (under
// 0.27 m where the bowl is 0.34-0.4 m), with seats of several heights; the plain generator's toilet is one bowl
// box 0.42 m high on the floor and its tank.
TEST(ApartmentGenerator, ShapeVarietyVariesToilets) {
  auto toilets = [](const Apartment& apt, int* hung, int* pedestal, std::set<int>* seat_cm) {
    std::map<int, std::vector<const SolidPart*>> parts;
    for (const SolidPart& p : apt.parts)
      if (!p.structural && p.label == nyu40::kToilet) parts[p.instance].push_back(&p);
    for (const auto& [instance, ps] : parts) {
      double lowest = 1e9, narrowest = 1e9, seat = 0;
      for (const SolidPart* p : ps) {
        const Eigen::Vector3d& s = p->box.size;
        const double bottom = p->box.center.z() - s.z() / 2 - apt.floor_z_m, top = bottom + s.z();
        lowest = std::min(lowest, bottom);
        if (bottom < 0.01 && top < 0.5) narrowest = std::min(narrowest, std::min(s.x(), s.y()));  // Not the tank.
        if (top < 0.5) seat = std::max(seat, top);
      }
      *hung += lowest > 0.1;
      *pedestal += lowest < 0.01 && narrowest < 0.27;
      if (seat > 0) seat_cm->insert(int(std::lround(seat * 100)));
    }
  };
  int hung = 0, pedestal = 0, plain_hung = 0, plain_pedestal = 0;
  std::set<int> seats, plain_seats;
  for (int seed = 0; seed < kSeeds; ++seed) {
    toilets(Generate(uint64_t(seed), true), &hung, &pedestal, &seats);
    toilets(Generate(uint64_t(seed)), &plain_hung, &plain_pedestal, &plain_seats);
  }
  EXPECT_GE(hung, 2);
  EXPECT_GE(pedestal, 4);
  EXPECT_GE(seats.size(), 4u);
  EXPECT_EQ(plain_hung, 0);
  EXPECT_EQ(plain_pedestal, 0);
  EXPECT_EQ(plain_seats, std::set<int>{42});
  std::printf("toilets with shape variety: %d hung, %d on a pedestal, %zu seat heights\n", hung, pedestal, seats.size());
}

TEST(ApartmentGenerator, ClosedRoomsAreSealedWithoutDoors) {
  // The flood fill above is meaningful: with the doors bricked up (their openings treated as walls),
  // no room but the first (and its open-plan partners) is reachable.
  const Apartment apt = Generate(7);
  ASSERT_GE(apt.rooms.size(), 3u);
  Apartment sealed = apt;
  for (const DoorGt& d : apt.doors) {
    SolidPart brick;
    brick.structural = true;
    brick.box.center = Eigen::Vector3d(d.center.x(), d.center.y(), apt.floor_z_m + 1.0);
    brick.box.size = d.along_x ? Eigen::Vector3d(d.width_m + 0.01, d.wall_thickness_m + 0.01, 2.0)
                               : Eigen::Vector3d(d.wall_thickness_m + 0.01, d.width_m + 0.01, 2.0);
    sealed.parts.push_back(brick);
  }
  const std::set<int> reached = ReachableRooms(sealed, false);
  EXPECT_EQ(reached.size(), 1 + apt.rooms[0].open_to.size());
}

TEST(ScanArtefacts, NothingLeftUnderBedsAndOptionsTurnOff) {
  const Apartment apt = Generate(7);
  ScanArtefactOptions off;
  off.remove_hidden = false;
  off.holes_per_m2 = 0;
  off.unscanned_ceiling_fraction = 0;
  off.vertex_noise_m = 0;
  const Mesh clean = ApplyScanArtefacts(apt, off);
  EXPECT_EQ(clean.faces.size(), apt.mesh.faces.size());
  EXPECT_EQ(clean.vertices, apt.mesh.vertices);

  ScanArtefactOptions on;
  on.seed = 7;
  const Mesh scanned = ApplyScanArtefacts(apt, on);
  EXPECT_LT(scanned.faces.size(), apt.mesh.faces.size());
  EXPECT_EQ(scanned.face_attributes.at("label").size(), scanned.faces.size());
  // No floor face lies wholly under a bed (0.07 m in from its outline, clear of the headboard).
  size_t beds = 0, under = 0, ceiling_before = 0, ceiling_after = 0;
  for (const ObjectGt& o : apt.objects) {
    if (o.label != nyu40::kBed) continue;
    ++beds;
    for (size_t f = 0; f < scanned.faces.size(); ++f) {
      if (scanned.face_attributes.at("label")[f] != nyu40::kFloor) continue;
      bool inside = true;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3f& c = scanned.vertices[size_t(scanned.faces[f][k])];
        const double cs = std::cos(o.box.yaw_rad), sn = std::sin(o.box.yaw_rad), dx = c.x() - o.box.center.x(), dy = c.y() - o.box.center.y();
        inside &= std::fabs(cs * dx + sn * dy) < o.box.size.x() / 2 - 0.07 && std::fabs(-sn * dx + cs * dy) < o.box.size.y() / 2 - 0.07;
      }
      under += inside;
    }
  }
  EXPECT_GT(beds, 0u);
  EXPECT_EQ(under, 0u);
  for (int l : apt.mesh.face_attributes.at("label")) ceiling_before += l == nyu40::kCeiling;
  for (int l : scanned.face_attributes.at("label")) ceiling_after += l == nyu40::kCeiling;
  EXPECT_LT(ceiling_after, ceiling_before);
  EXPECT_GT(ceiling_after, ceiling_before / 2);
  // Vertex noise keeps coincident corners together: shared positions stay shared.
  ScanArtefactOptions noise_only = off;
  noise_only.vertex_noise_m = 0.01;
  const Mesh noisy = ApplyScanArtefacts(apt, noise_only);
  std::map<std::array<float, 3>, Eigen::Vector3f> moved;
  for (size_t v = 0; v < apt.mesh.vertices.size(); ++v) {
    const Eigen::Vector3f& p = apt.mesh.vertices[v];
    const auto [it, fresh] = moved.emplace(std::array<float, 3>{p.x(), p.y(), p.z()}, noisy.vertices[v]);
    if (!fresh) {
      EXPECT_EQ(it->second, noisy.vertices[v]);
    }
  }
}

TEST(ApartmentGroundTruth, RoomsImageMatchesRoomPolygons) {
  const Apartment apt = Generate(3);
  const FloorGrid g = MakeFloorGrid(apt, GroundTruthOptions());
  const ImageU16 img = RasterizeRooms(apt, g);
  for (const RoomGt& r : apt.rooms) {
    size_t n = 0;
    for (uint16_t v : img.data) n += v == r.id;
    // Pixel centres inside the polygon: the area up to a pixel along the perimeter.
    const double perimeter = 2 * ((r.x1 - r.x0) + (r.y1 - r.y0));
    EXPECT_NEAR(n * g.resolution * g.resolution, r.area_m2(), perimeter * g.resolution / 2) << "room " << r.id;
  }
  // Row 0 is the largest y.
  const RoomGt& r0 = apt.rooms[0];
  int c, row;
  ASSERT_TRUE(g.PixelOf(0.5 * (r0.x0 + r0.x1), r0.y1 - 0.01, &c, &row));
  EXPECT_EQ(img.at(c, row), r0.id);
  EXPECT_NEAR(g.CenterY(row), r0.y1 - 0.025, 0.026);
}

TEST(ApartmentGenerator, RejectsBadOptionsNamingTheField) {
  ApartmentOptions bad;
  bad.max_rooms = 9;
  std::string error;
  EXPECT_FALSE(bad.Check(&error));
  EXPECT_NE(error.find("max_rooms = 9"), std::string::npos) << error;
  EXPECT_FALSE(GenerateApartment(bad).ok());
}

}  // namespace
}  // namespace semvox
