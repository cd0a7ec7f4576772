// Private to the render module: the Embree side of a Raycaster. Only render/*.cc include this header;
// no public header may include it (it pulls in Embree).
#pragma once

#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <vector>

#include "render/raycaster.h"

namespace semvox {

// The process-wide Embree device, created on first use with its error callback set (once).
RTCDevice SharedEmbreeDevice();

struct Raycaster::Impl {
  RTCScene scene = nullptr;
  bool is_cloud = false;
  // Geometry shared with Embree (rtcSetSharedGeometryBuffer), so it is stored once. Vertices are packed
  // x,y,z (meshes) or x,y,z,radius (clouds) with one float of padding at the end, as Embree requires.
  std::vector<float> vertex_data;
  std::vector<Eigen::Vector3i> faces;
  std::vector<float> normal_data;  // Clouds: x,y,z per point, plus padding.
  std::vector<float> radii;        // Clouds: disc radius per disc.
  std::vector<int32_t> disc_point; // Clouds with merged discs: the point index each disc reports; empty: disc = point.
  size_t num_primitives = 0;
  bool squares = false;            // Clouds drawn as two triangles per disc (vertex_data: x,y,z corners).

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
  }

  Eigen::Vector3f Vertex(int i) const {
    return Eigen::Vector3f(vertex_data[3 * size_t(i)], vertex_data[3 * size_t(i) + 1], vertex_data[3 * size_t(i) + 2]);
  }
  // Exact surface point of a mesh hit from its barycentrics, in double (see Raycaster::HitPoint).
  Eigen::Vector3d MeshPoint(int face, float u, float v) const {
    const Eigen::Vector3i& f = faces[face];
    const Eigen::Vector3d a = Vertex(f[0]).cast<double>();
    return a + double(u) * (Vertex(f[1]).cast<double>() - a) + double(v) * (Vertex(f[2]).cast<double>() - a);
  }
};

// Fills an RTCRayHit16 lane from a Ray; lanes not filled must be masked invalid by the caller.
inline void SetPacketRay(RTCRayHit16& p, int lane, const Ray& r) {
  p.ray.org_x[lane] = r.origin.x();
  p.ray.org_y[lane] = r.origin.y();
  p.ray.org_z[lane] = r.origin.z();
  p.ray.dir_x[lane] = r.direction.x();
  p.ray.dir_y[lane] = r.direction.y();
  p.ray.dir_z[lane] = r.direction.z();
  p.ray.tnear[lane] = r.t_min;
  p.ray.tfar[lane] = r.t_max;
  p.ray.time[lane] = 0.0f;
  p.ray.mask[lane] = 0xFFFFFFFFu;
  p.ray.id[lane] = unsigned(lane);
  p.ray.flags[lane] = 0;
  p.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
  p.hit.primID[lane] = RTC_INVALID_GEOMETRY_ID;
  p.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace semvox
