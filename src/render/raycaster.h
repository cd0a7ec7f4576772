// Ray casting against a scanned scene: the one place semvox talks to Embree.
//
// A Raycaster is built once from a Mesh (triangles) or a PointCloud (each point an oriented disc sized to
// the local point spacing) and then answers ray queries from any number of threads:
//
//   Result<Raycaster> rc = Raycaster::FromMesh(scene.mesh);
//   if (!rc.ok()) return rc.status();
//   Ray ray{origin, direction};                    // direction need not be unit length
//   RayHit hit = rc->Intersect(ray);
//   if (hit.hit()) {
//     Eigen::Vector3d p = rc->HitPoint(ray, hit);  // on the surface (exact for mesh faces)
//     ... hit.primitive (face or point index), hit.u / hit.v (barycentrics), hit.normal ...
//   }
//
// Batches use 16-ray packets over all cores (TBB):  rc->Intersect(rays, &hits);
//
// Embree types stay in raycaster.cc; the geometry is copied into Embree, so the Mesh or PointCloud need
// not outlive the Raycaster. The Embree device is shared by all Raycasters and its error callback is set
// once when it is created.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "core/status.h"

namespace semvox {

struct Ray {
  Eigen::Vector3f origin = Eigen::Vector3f::Zero();
  Eigen::Vector3f direction = Eigen::Vector3f::UnitX();  // Need not be unit length; must be non-zero.
  float t_min = 0.0f;                                     // Hits with t < t_min are ignored.
  float t_max = std::numeric_limits<float>::infinity();   // Hits with t > t_max are ignored.
};

struct RayHit {
  // Ray parameter of the hit: point = origin + distance * direction. Metres when direction is unit length.
  // +infinity on a miss.
  float distance = std::numeric_limits<float>::infinity();
  // Face index (meshes) or point index (clouds); -1 on a miss.
  int32_t primitive = -1;
  // Barycentric coordinates on face `primitive`: point = (1-u-v) v0 + u v1 + v v2, as Mesh::ColorAt takes
  // them. Zero for clouds.
  float u = 0.0f, v = 0.0f;
  // Unit geometric normal (face normal or disc normal), flipped to face the ray origin
  // (normal . direction <= 0). Zero on a miss.
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();

  bool hit() const { return primitive >= 0; }
};

struct RaycasterOptions {
  // Point clouds only: disc radius = point_radius_factor * local spacing (mean distance to the
  // spacing_neighbors nearest points), so that neighbouring discs overlap and surfaces are closed. > 0.
  double point_radius_factor = 1.0;
  // Point clouds only: k for the local spacing and (when the cloud has no normals) PCA normals. [3, 100].
  int spacing_neighbors = 8;
  // Point clouds only: merge the points of each cube of this side into one disc, metres (0: one disc per
  // point). The disc sits at the points' centroid with their mean normal (or, without normals, the PCA normal
  // of its spacing_neighbors nearest discs: a neighbourhood as many times wider as the cells are); its
  // primitive id is the point nearest the centroid, so colours and per-point attributes still come from the
  // cloud. Fewer, larger discs cost about what a mesh of the same scene costs to trace. [0, 1].
  double cloud_cell_m = 0.0;
  // Point clouds only: draw each disc as the square of the same radius around it (half side = radius, in the
  // disc's plane), two triangles for Embree's fast triangle intersectors instead of an oriented disc.
  bool cloud_squares = false;
  // Embree's robust (watertight) triangle test for meshes: no ray slips between two faces that share an edge.
  // Costs a few percent of speed. Cloud squares (cloud_squares) never use it: they overlap their neighbours.
  bool robust = true;

  bool Check(std::string* error) const;
};

class Raycaster {
 public:
  // Builds the acceleration structure. Errors (kInvalidInput) for an empty mesh, a face index out of
  // range or non-finite coordinates; kInternal when Embree fails (the message carries Embree's).
  static Result<Raycaster> FromMesh(const Mesh& mesh, const RaycasterOptions& options = {});
  static Result<Raycaster> FromCloud(const PointCloud& cloud, const RaycasterOptions& options = {});
  // A mesh or a cloud, whichever the scene holds.
  static Result<Raycaster> FromScene(const Scene& scene, const RaycasterOptions& options = {});

  Raycaster(Raycaster&&) noexcept;
  Raycaster& operator=(Raycaster&&) noexcept;
  ~Raycaster();

  bool is_cloud() const;
  size_t num_primitives() const;  // Faces or points.
  // Disc radius of each disc (clouds only; empty for meshes), metres: one per point, or one per occupied
  // cell with RaycasterOptions::cloud_cell_m > 0.
  const std::vector<float>& point_radii() const;
  // Clouds with cloud_cell_m > 0: the point each disc reports as its primitive (empty otherwise).
  const std::vector<int32_t>& disc_points() const;

  // Closest hit along one ray. Thread-safe.
  RayHit Intersect(const Ray& ray) const;
  // Closest hits of many rays, in 16-ray packets spread over all cores. hits is resized to rays.size().
  void Intersect(std::span<const Ray> rays, std::vector<RayHit>* hits) const;
  // Same without parallelism (for callers that are already parallel).
  void IntersectSerial(std::span<const Ray> rays, std::span<RayHit> hits) const;

  // The hit point. For meshes it is interpolated from the face's vertices with the barycentrics (in
  // double), so it lies on the face exactly: a point on an axis-aligned wall has that wall's coordinate.
  // For clouds it is origin + distance * direction. Undefined for misses.
  Eigen::Vector3d HitPoint(const Ray& ray, const RayHit& hit) const;

  struct Impl;  // Defined in render/embree_scene.h, for the render module's own .cc files only.
  const Impl& impl() const { return *impl_; }

 private:
  explicit Raycaster(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace semvox
