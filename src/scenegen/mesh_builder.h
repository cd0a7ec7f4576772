// Building labelled meshes from primitives (boxes, quads). Used by the scene generator, the bundled
// demo scene and the analytic test scenes. Every face carries `label` (NYU40 id), `instance` and `room`.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/geometry.h"

namespace semvox {

struct FaceTags {
  int label = 0;      // NYU40 id.
  int instance = -1;  // Object instance id, -1 for none.
  int room = -1;      // Room id, -1 for none.
};

class MeshBuilder {
 public:
  MeshBuilder();
  // Axis-aligned box [lo, hi] rotated by `yaw_rad` about the vertical axis through its centre. Faces
  // point outwards. `skip_bottom` leaves out the face touching what the box stands on.
  void AddBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Rgb8 color, const FaceTags& tags,
              double yaw_rad = 0.0, bool skip_bottom = false);
  // A planar quad a-b-c-d (counter-clockwise seen from the side its normal points to).
  void AddQuad(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& d,
               Rgb8 color, const FaceTags& tags);
  void AddTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, Rgb8 color,
                   const FaceTags& tags);
  const Mesh& mesh() const { return mesh_; }
  Mesh Take() { return std::move(mesh_); }

 private:
  Mesh mesh_;
};

}  // namespace semvox
