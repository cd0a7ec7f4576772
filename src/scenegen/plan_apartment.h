// Apartments built on a given floor plan (real layouts such as the R2V plans of ../shared/data/r2v) instead of
// a drawn one: walls extruded from wall centre lines, door gaps with lintels, windows cut into exterior walls,
// the plan's fixtures as boxes, floors and ceilings over the rooms. The result is an ordinary Apartment:
// WriteApartment, ApplyScanArtefacts and SimulateScan work on it as on a generated one.
//
//   PlanLayout layout;       // metres: wall and door segments, fixtures, a room-id raster with a type per room
//   Result<Apartment> apt = ApartmentFromLayout(layout, PlanApartmentOptions{});
//
// Rooms need not be rectangles: the room ground truth is the layout's raster (Apartment::room_raster), and
// RoomGt's x0..y1 is the room's bounding box. The plan's fixtures are boxes; the other typed rooms are
// furnished by type inside the largest rectangle of their floor (PlanApartmentOptions::furniture).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/image.h"
#include "core/status.h"
#include "scenegen/apartment.h"

namespace semvox {

struct PlanLayout {
  struct Segment {
    Eigen::Vector2d a = Eigen::Vector2d::Zero(), b = Eigen::Vector2d::Zero();
  };
  struct Fixture {
    Eigen::Vector2d lo = Eigen::Vector2d::Zero(), hi = Eigen::Vector2d::Zero();  // Footprint box, metres.
    int label = 0;                                                               // NYU40 id.
  };
  std::vector<Segment> walls;  // Wall centre lines.
  std::vector<Segment> doors;  // Door openings, lying on walls.
  std::vector<Fixture> fixtures;
  // Room id per pixel (0: no room: outside, walls, doors); pixel (c, r) covers
  // [origin.x + c res, origin.x + (c + 1) res) x [origin.y + r res, origin.y + (r + 1) res).
  ImageU16 rooms;
  double resolution_m = 0.05;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  std::vector<int> room_type;  // Per room id (index 0 unused): room_types.tsv id, 0 untyped.
};

struct PlanApartmentOptions {
  uint64_t seed = 0;              // Colours and which walls get windows.
  double ceiling_m = 2.4;         // Wall height, metres. [2, 4].
  double wall_m = 0.12;           // Wall thickness, metres. [0.05, 0.4].
  double door_height_m = 2.05;    // Top of the door gaps (lintels above). (0, ceiling_m).
  double window_sill_m = 0.9;     // Windows: sill and top above the floor, metres; 0 < sill < top < ceiling_m.
  double window_top_m = 2.1;
  double min_window_wall_m = 1.4; // Exterior wall pieces at least this long (between doors) get a window. > 0.
  double surface_cell_m = 0.25;   // As ApartmentOptions::surface_cell_m. > 0.
  // Regions of the raster smaller than this are no rooms (pipe shafts, cupboards no one walks into): left
  // out of the ground truth, their floor kept, m². >= 0.
  double min_room_area_m2 = 0.5;
  // Furniture by room type (the generator's, scenegen/furniture.cc) in each typed room that holds no fixture
  // of the plan, inside the largest axis-aligned rectangle of its floor clear of walls, door gaps and
  // fixtures; with props on its support surfaces and the floor.
  bool furniture = true;
  bool props = true;

  bool Check(std::string* error) const;
};

// Fails on invalid options, a layout without rooms, or segments that are not finite.
Result<Apartment> ApartmentFromLayout(const PlanLayout& layout, const PlanApartmentOptions& options);

}  // namespace semvox
