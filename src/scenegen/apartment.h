// Random labelled apartments: the synthetic data every accuracy figure of semvox is measured on.
//
//   ApartmentOptions (seed) --GenerateApartment--> Apartment (clean labelled mesh + ground truth)
//   Apartment --ApplyScanArtefacts--> mesh as a scanner would deliver it (scan_artefacts.h)
//   Apartment --WriteApartment--> mesh.ply, gt_mesh.ply, gt.json, rooms_gt.png (apartment_io.h)
//
// An apartment is 1-8 axis-aligned rectangular rooms typed from room_types.tsv (living room, kitchen,
// bathroom, bedrooms, a corridor or hall, office, storage, laundry, ...), with an open-plan kitchen or a
// studio sometimes, walls 0.1-0.25 m thick, doors joining every room (a spanning tree over shared walls),
// windows in exterior walls, furniture by room type built from boxes, and small props on support
// surfaces. Frame: metres, x east, y north, +z up, floor at z = floor_z_m. Every face carries its NYU40
// `label`, object `instance` (-1 for walls, floors and ceilings) and `room` (1-based id, -1 for none).
// The same options give the same apartment, bit for bit (scenegen/random.h).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "core/image.h"
#include "core/status.h"

namespace semvox {

struct ApartmentOptions {
  uint64_t seed = 0;              // Everything random derives from this.
  int min_rooms = 1;              // Fewest rooms (typed areas, corridor and open-plan areas included). [1, 8].
  int max_rooms = 8;              // Most rooms. [min_rooms, 8].
  double floor_z_m = 0.0;         // Height of the floor, metres.
  double min_ceiling_m = 2.3;     // Ceiling height above the floor is drawn in [min, max], metres.
  double max_ceiling_m = 2.9;
  double min_wall_m = 0.10;       // Interior walls are drawn in [min_wall, min_wall + 0.05], exterior
  double max_wall_m = 0.25;       // walls in [max_wall - 0.05, max_wall], metres.
  double surface_cell_m = 0.25;   // Walls, floors and ceilings are tessellated into cells of about this
                                  // size (small cells let holes and occlusion removal act locally). > 0.
  bool furniture = true;          // Furniture per room type.
  bool props = true;              // Small props (books, boxes, bags, clothes, paper, ...) on supports.
  bool shape_variety = false;     // More furniture shapes (L-shaped sofas, seat cushions, bar tables, bins,
                                  // pedestal desks, free-standing cabinets): the randomised training and
                                  // validation scans use it; off, the apartments of a seed stay as they were.
  int max_attempts = 200;         // Layout attempts before giving up (each draws a new layout).

  bool Check(std::string* error) const;
};

// An oriented box: centre, full size along its own axes, and rotation about +z (radians).
struct OrientedBox {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
};

struct RoomGt {
  int id = 0;                      // 1-based; the value painted in rooms_gt.png.
  int type_id = 0;                 // room_types.tsv id.
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // Clear interior (inner faces of walls), metres.
  std::vector<int> open_to;        // Rooms sharing this space with no wall in between (open plan).
  double area = 0;                 // Floor area when the room is not its box (plan apartments), m²; 0: the box.
  double area_m2() const { return area > 0 ? area : (x1 - x0) * (y1 - y0); }
};

struct ObjectGt {
  int instance = 0;   // Face attribute `instance`.
  int label = 0;      // NYU40 id.
  int room = -1;      // Room id.
  int support_of = -1;  // Instance it stands on or hangs from (lamp on a night stand), -1 for none.
  OrientedBox box;    // Bounding box of all its parts, in its own (yawed) frame.
};

struct DoorGt {
  int room_a = -1, room_b = -1;  // -1 on one side for the entrance door.
  Eigen::Vector2d center = Eigen::Vector2d::Zero();  // Middle of the opening at floor level.
  bool along_x = true;           // The wall runs along x (else along y).
  double width_m = 0, height_m = 0, wall_thickness_m = 0;
};

struct WindowGt {
  int room = -1;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  bool along_x = true;
  double width_m = 0, sill_m = 0, top_m = 0;  // Heights above the floor.
};

// A solid box the mesh was built from (wall piece, furniture part). Used to remove faces hidden inside
// or against other solids and by the tests (no furniture intersects walls or other furniture).
struct SolidPart {
  OrientedBox box;
  int instance = -1;   // Object instance, -1 for walls.
  int label = 0;
  bool structural = false;  // Wall piece.
  int support_of = -1;      // Instance this part rests on (props, lamps, TVs), -1 when on the floor.
};

struct Apartment {
  uint64_t seed = 0;
  Mesh mesh;                      // Clean labelled mesh (no scan artefacts).
  std::vector<int> face_part;     // Per face: index into parts, -1 for floors, ceilings and wall faces.
  std::vector<SolidPart> parts;
  std::vector<RoomGt> rooms;
  std::vector<ObjectGt> objects;
  std::vector<DoorGt> doors;
  std::vector<WindowGt> windows;
  double floor_z_m = 0.0;
  double ceiling_z_m = 2.6;
  double interior_wall_m = 0.1, exterior_wall_m = 0.2;
  Aabb bounds;                    // Of the mesh.
  // Rooms that are not rectangles (apartments on a given plan, plan_apartment.h): room id per pixel, pixel
  // (c, r) covering [origin + (c, r) res, origin + (c + 1, r + 1) res). Empty: the rooms are their boxes.
  ImageU16 room_raster;
  std::string plan;               // The plan file it was built on (gt.json "plan"), empty for drawn layouts.
  double room_raster_m = 0.05;
  Eigen::Vector2d room_raster_origin = Eigen::Vector2d::Zero();
};

// The id of the room whose floor holds (x, y), 0 for none: from room_raster when there is one, else the
// first room box holding it.
int RoomIdAt(const Apartment& apt, double x, double y);

// Draws one apartment. Fails only on invalid options (or when no layout fits in max_attempts, which the
// default options never hit).
Result<Apartment> GenerateApartment(const ApartmentOptions& options);

}  // namespace semvox
