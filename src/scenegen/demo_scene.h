// The bundled demo apartment (scenes/demo_apartment.ply): three rooms with doors, a window and
// furniture, built from primitives with NYU40 labels, instances and room ids per face.
#pragma once

#include "core/geometry.h"
#include "scenegen/mesh_builder.h"

namespace semvox {

// Wall of `thickness` along the segment a-b (horizontal), from z0 to z1, with door openings given as
// intervals [s0, s1] of distance along the segment (metres from a) up to `door_height`.
struct WallOpening {
  double from_m, to_m, bottom_m, top_m;
};
void AddWall(MeshBuilder* b, const Eigen::Vector2d& a, const Eigen::Vector2d& c, double thickness, double z0, double z1,
             const std::vector<WallOpening>& openings, Rgb8 color, const FaceTags& tags);

// A table: top of size (sx, sy, thickness) at height h plus four legs.
void AddTable(MeshBuilder* b, const Eigen::Vector2d& centre, double sx, double sy, double h, Rgb8 color,
              const FaceTags& tags, double yaw_rad = 0.0);

Mesh BuildDemoApartment();

}  // namespace semvox
