// Internal to the apartment generator: building geometry (walls, floors, composed furniture) into an
// Apartment while keeping its ground truth (objects, solid parts, support surfaces) in step.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "scenegen/apartment.h"
#include "scenegen/layout.h"
#include "scenegen/mesh_builder.h"
#include "scenegen/random.h"

namespace semvox {
namespace scenegen {

// Where an object stands: footprint centre (x, y) on the floor at height z, rotated by yaw about +z.
// Object-local frame: x along the object's width, y along its depth with the front towards +y (away
// from the wall it stands against), z up from its base.
struct Pose {
  double x = 0, y = 0, yaw = 0, z = 0;
  Eigen::Vector2d ToWorld(double lx, double ly) const;
};

// A 2-D oriented footprint with a height interval: what furniture placement checks overlaps against.
struct Footprint {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  double hx = 0, hy = 0, yaw = 0;  // Half extents along the rotated axes.
  double z0 = 0, z1 = 0;
};
bool Overlaps(const Footprint& a, const Footprint& b);

// A horizontal surface props can stand on (table top, shelf board, bed, counter, floor spot).
struct Support {
  Pose pose;                // Centre of the usable rectangle at its height.
  double hx = 0, hy = 0;    // Half extents of the usable rectangle.
  double max_height = 0.3;  // Free height above it.
  int instance = -1;        // The furniture it belongs to.
  std::vector<Footprint> taken;
};

class ApartmentBuilder {
 public:
  ApartmentBuilder(Apartment* apartment, double surface_cell_m);

  // A planar rectangle o + s*u + t*v (s in [0, lu], t in [0, lv]), tessellated into cells of about
  // surface_cell_m, facing u x v. `part` is the solid it lies on (-1 for none).
  void AddSurface(const Eigen::Vector3d& o, const Eigen::Vector3d& u, double lu, const Eigen::Vector3d& v, double lv,
                  Rgb8 color, const FaceTags& tags, int part);
  // Registers a solid without emitting faces (wall pieces; their visible faces are added by AddSurface).
  int AddSolid(const OrientedBox& box, int label, int instance, bool structural);

  // Composed objects: Begin, then Box() parts in the object's local frame, then End().
  int Begin(int label, int room, const Pose& pose, int support_of = -1);
  void Box(double x0, double y0, double z0, double x1, double y1, double z1, Rgb8 color, bool skip_bottom = false);
  const ObjectGt& End();
  // Footprint of the current object's parts so far (world frame), for collision bookkeeping.
  Footprint CurrentFootprint() const;

  Apartment* apartment() { return apartment_; }
  MeshBuilder& mesh() { return mesh_; }
  int next_instance() const { return next_instance_; }
  void Finish();

 private:
  Apartment* apartment_;
  MeshBuilder mesh_;
  double cell_;
  int next_instance_ = 0;
  // Current object.
  ObjectGt current_;
  Pose pose_;
  int support_of_ = -1;
  Eigen::Vector3d local_lo_, local_hi_;
};

// Furnishes every room of the plan (furniture by room type, then props).
// `variety`: ApartmentOptions::shape_variety (no extra random draws when false).
void FurnishApartment(const FloorPlan& plan, bool props, bool variety, Rng* rng, ApartmentBuilder* builder);

}  // namespace scenegen
}  // namespace semvox
