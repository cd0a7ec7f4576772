// Internal to the apartment generator: the floor plan (room rectangles, shared walls, doors, windows)
// before any geometry is built. Exposed in a header so the tests can check the plan directly.
#pragma once

#include <string>
#include <vector>

#include "scenegen/random.h"

namespace semvox {
namespace scenegen {

// Room type ids of room_types.tsv, looked up by name once (never pasted numbers).
struct RoomTypeIds {
  int bathroom, bedroom, childs_room, corridor, dining_room, kitchen, laundry, living_room, office, storage;
  static const RoomTypeIds& Get();
};

struct Rect {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double w() const { return x1 - x0; }
  double h() const { return y1 - y0; }
  double area() const { return w() * h(); }
};

// Sides of a room rectangle, counter-clockwise from the south; the inward normal of side s is
// (0,1), (-1,0), (0,-1), (1,0) and furniture against side s has yaw s * 90 degrees.
enum Side { kSouth = 0, kEast = 1, kNorth = 2, kWest = 3 };

// A piece of a room side: [a, b] along the side's axis (x for south / north, y for east / west),
// shared with `neighbor` (-1: exterior wall) and open (no wall) when both rooms are one open-plan space.
struct SideSegment {
  double a = 0, b = 0;
  int neighbor = -1;
  bool open = false;
};

struct Opening {
  int side = 0;        // Side of room `room` it is cut into (the same wall seen from the neighbour too).
  double a = 0, b = 0; // Along the side's axis.
  double bottom = 0, top = 0;  // Above the floor.
  bool door = true;
};

struct PlanRoom {
  int type = 0;
  double target_area = 0;   // m², of the cell (walls included).
  bool studio = false;      // A one-room flat: sleeping, living and a kitchenette in one space.
  int open_group = -1;      // Rooms with the same group share one space (open plan).
  Rect cell;                // Up to the wall centre lines.
  Rect interior;            // Clear interior (after walls).
  std::vector<SideSegment> sides[4];
  double shrink[4] = {0, 0, 0, 0};  // Wall half thickness taken from the cell on each side.
};

struct PlanDoor {
  int room_a = -1, room_b = -1;  // room_b = -1: entrance (exterior wall of room_a).
  int side_a = 0;                // Side of room_a.
  double a = 0, b = 0;           // Opening along the side's axis.
  double height = 2.05;
};

struct PlanWindow {
  int room = -1, side = 0;
  double a = 0, b = 0, sill = 0.9, top = 2.1;
};

struct FloorPlan {
  std::vector<PlanRoom> rooms;
  std::vector<PlanDoor> doors;
  std::vector<PlanWindow> windows;
  double interior_wall = 0.1, exterior_wall = 0.2, ceiling = 2.6;
  // Scales the walkway kept free in front of furniture against a wall (beds, wardrobes, counters): 1 in drawn
  // layouts; smaller in the tighter rooms of real plans (plan_apartment.h).
  double front_clearance_scale = 1.0;
  // Depth of the swing square kept clear in front of a door: its width, at most this (wide openings and
  // sliding doors of real plans need a walkway, not a square as deep as they are wide).
  double max_door_swing = 1e9;
  // A bedroom whose double bed finds no place against a wall tries a single bed (real plans).
  bool single_bed_fallback = false;
  // A room's defining furniture (a bedroom's bed, a living room's sofa) that the random draws against the walls
  // do not place is looked for at every spot along every wall (5 cm steps), then without the walkway in front
  // of it, then keeping only a door's passage (0.3 m) clear instead of its swing square (real plans, whose
  // doors are often sliding), then before as few doors as possible (Japanese rooms with a sliding door on every
  // wall). One of the spots found is drawn; nothing is placed when the room is too small for it.
  bool place_defining_furniture = false;
};

// Draws a plan with `num_rooms` rooms; false when this draw does not fit (the caller draws again).
bool DrawFloorPlan(int num_rooms, double ceiling_m, double interior_wall_m, double exterior_wall_m, Rng* rng,
                   FloorPlan* plan);

}  // namespace scenegen
}  // namespace semvox
