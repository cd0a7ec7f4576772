#include "render/raycaster.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <limits>

#include <cmath>
#include <cstring>
#include <mutex>
#include <sstream>

#include "core/log.h"
#include "mapping/cloud_geometry.h"
#include "render/embree_scene.h"

namespace semvox {
namespace {

const char* EmbreeErrorName(RTCError e) {
  switch (e) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_UNKNOWN: return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
  }
  return "unrecognised error";
}

// The last message Embree reported on this thread, for the Status returned to the caller.
thread_local std::string g_last_embree_message;

void OnEmbreeError(void* /*user*/, RTCError code, const char* message) {
  std::ostringstream os;
  os << "Embree: " << EmbreeErrorName(code) << (message ? std::string(": ") + message : std::string());
  g_last_embree_message = os.str();
  SEMVOX_WARN(g_last_embree_message);
}

struct DeviceHolder {
  RTCDevice device = nullptr;
  DeviceHolder() {
    device = rtcNewDevice(nullptr);
    if (device) rtcSetDeviceErrorFunction(device, OnEmbreeError, nullptr);
  }
  ~DeviceHolder() {
    if (device) rtcReleaseDevice(device);
  }
};

Status EmbreeFailure(const std::string& what) {
  RTCError code = rtcGetDeviceError(SharedEmbreeDevice());
  std::string detail = g_last_embree_message.empty() ? EmbreeErrorName(code) : g_last_embree_message;
  return Status::Internal(what + " failed: " + detail + " (hint: check free memory; Embree needs SSE2 or better)");
}

// Commits `geom` into a new scene in impl; returns an error naming `what` on failure.
Status CommitScene(RTCGeometry geom, bool robust, Raycaster::Impl* impl, const std::string& what) {
  rtcCommitGeometry(geom);
  impl->scene = rtcNewScene(SharedEmbreeDevice());
  if (!impl->scene) {
    rtcReleaseGeometry(geom);
    return EmbreeFailure(what + ": rtcNewScene");
  }
  rtcSetSceneFlags(impl->scene, robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
  rtcSetSceneBuildQuality(impl->scene, RTC_BUILD_QUALITY_MEDIUM);
  rtcAttachGeometry(impl->scene, geom);
  rtcReleaseGeometry(geom);  // The scene holds the reference now.
  g_last_embree_message.clear();
  rtcCommitScene(impl->scene);
  if (rtcGetDeviceError(SharedEmbreeDevice()) != RTC_ERROR_NONE || !g_last_embree_message.empty())
    return EmbreeFailure(what + ": building the acceleration structure");
  return Status::Ok();
}

RayHit ToHit(const RTCRayHit16& p, int lane, const std::vector<int32_t>& disc_point) {
  RayHit h;
  if (p.hit.geomID[lane] == RTC_INVALID_GEOMETRY_ID) return h;
  h.distance = p.ray.tfar[lane];
  h.primitive = disc_point.empty() ? int32_t(p.hit.primID[lane]) : disc_point[p.hit.primID[lane]];
  h.u = p.hit.u[lane];
  h.v = p.hit.v[lane];
  Eigen::Vector3f n(p.hit.Ng_x[lane], p.hit.Ng_y[lane], p.hit.Ng_z[lane]);
  const Eigen::Vector3f d(p.ray.dir_x[lane], p.ray.dir_y[lane], p.ray.dir_z[lane]);
  const float len = n.norm();
  n = len > 0 ? Eigen::Vector3f(n / len) : Eigen::Vector3f(-d.normalized());
  if (n.dot(d) > 0) n = -n;
  h.normal = n;
  return h;
}

// The points of each occupied cube of side `cell`, merged: centroid, mean normal (when the cloud has normals)
// and the point nearest the centroid (ties: the lower index). Cells in key order, so the result depends on
// the points alone.
struct MergedCloud {
  PointCloud cloud;                    // points (and normals) of the merged discs.
  std::vector<int32_t> representative; // Per disc, a point of `cloud`'s source.
};

MergedCloud MergeCloudCells(const PointCloud& cloud, double cell) {
  const size_t n = cloud.points.size();
  const bool normals = cloud.normals.size() == n;
  // Cell coordinates in 21 bits each (+-1 M cells: +-50 km at 5 cm), packed into one sortable key.
  constexpr int64_t kBias = int64_t(1) << 20, kMask = (int64_t(1) << 21) - 1;
  std::vector<std::pair<uint64_t, uint32_t>> keyed(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      uint64_t key = 0;
      for (int a = 0; a < 3; ++a) {
        const int64_t c = std::clamp<int64_t>(int64_t(std::floor(double(cloud.points[i][a]) / cell)) + kBias, 0, kMask);
        key = (key << 21) | uint64_t(c);
      }
      keyed[i] = {key, uint32_t(i)};
    }
  });
  tbb::parallel_sort(keyed.begin(), keyed.end());  // Pairs are distinct: the order is unique.
  MergedCloud m;
  for (size_t b = 0; b < n;) {
    size_t e = b;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(), nsum = Eigen::Vector3d::Zero();
    for (; e < n && keyed[e].first == keyed[b].first; ++e) {
      sum += cloud.points[keyed[e].second].cast<double>();
      if (normals) {
        Eigen::Vector3d v = cloud.normals[keyed[e].second].cast<double>();
        if (nsum.dot(v) < 0) v = -v;  // Normals of one surface may point either way.
        nsum += v;
      }
    }
    const Eigen::Vector3d centroid = sum / double(e - b);
    uint32_t best = keyed[b].second;
    double best_d = std::numeric_limits<double>::infinity();
    for (size_t j = b; j < e; ++j) {
      const double d = (cloud.points[keyed[j].second].cast<double>() - centroid).squaredNorm();
      if (d < best_d || (d == best_d && keyed[j].second < best)) best = keyed[j].second, best_d = d;
    }
    m.cloud.points.push_back(centroid.cast<float>());
    if (normals) m.cloud.normals.push_back(nsum.norm() > 0 ? Eigen::Vector3f(nsum.normalized().cast<float>()) : cloud.normals[best]);
    m.representative.push_back(int32_t(best));
    b = e;
  }
  return m;
}

}  // namespace

RTCDevice SharedEmbreeDevice() {
  static DeviceHolder holder;
  return holder.device;
}

bool RaycasterOptions::Check(std::string* error) const {
  std::ostringstream os;
  if (!(point_radius_factor > 0) || !std::isfinite(point_radius_factor))
    os << "point_radius_factor = " << point_radius_factor << ". Violated constraint: point_radius_factor > 0";
  else if (spacing_neighbors < 3 || spacing_neighbors > 100)
    os << "spacing_neighbors = " << spacing_neighbors << ". Violated constraint: 3 <= spacing_neighbors <= 100";
  else if (!(cloud_cell_m >= 0 && cloud_cell_m <= 1))
    os << "cloud_cell_m = " << cloud_cell_m << ". Violated constraint: 0 <= cloud_cell_m <= 1";
  if (os.str().empty()) return true;
  if (error) *error = os.str();
  return false;
}

Raycaster::Raycaster(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Raycaster::Raycaster(Raycaster&&) noexcept = default;
Raycaster& Raycaster::operator=(Raycaster&&) noexcept = default;
Raycaster::~Raycaster() = default;

bool Raycaster::is_cloud() const { return impl_->is_cloud; }
size_t Raycaster::num_primitives() const { return impl_->num_primitives; }
const std::vector<float>& Raycaster::point_radii() const { return impl_->radii; }
const std::vector<int32_t>& Raycaster::disc_points() const { return impl_->disc_point; }

Result<Raycaster> Raycaster::FromMesh(const Mesh& mesh, const RaycasterOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("render options: " + error);
  if (mesh.faces.empty() || mesh.vertices.empty())
    return Status::InvalidInput("mesh has no faces to render (hint: a point cloud needs Raycaster::FromCloud)");
  if (!SharedEmbreeDevice()) return EmbreeFailure("rtcNewDevice");
  auto impl = std::make_unique<Impl>();
  const size_t nv = mesh.vertices.size();
  impl->vertex_data.resize(3 * nv + 1, 0.0f);  // +1: Embree reads vertices with 16-byte loads.
  for (size_t i = 0; i < nv; ++i) {
    const Eigen::Vector3f& p = mesh.vertices[i];
    if (!p.allFinite())
      return Status::InvalidInput("mesh vertex " + std::to_string(i) + " is not finite (hint: load through LoadScene, which drops them)");
    std::memcpy(&impl->vertex_data[3 * i], p.data(), 3 * sizeof(float));
  }
  impl->faces.resize(mesh.faces.size() + 1);  // +1 padding, never indexed by Embree.
  for (size_t i = 0; i < mesh.faces.size(); ++i) {
    const Eigen::Vector3i& f = mesh.faces[i];
    if ((f.array() < 0).any() || (f.array() >= int(nv)).any())
      return Status::InvalidInput("mesh face " + std::to_string(i) + " uses a vertex index out of range [0, " +
                                  std::to_string(nv) + ")");
    impl->faces[i] = f;
  }
  impl->num_primitives = mesh.faces.size();

  RTCGeometry geom = rtcNewGeometry(SharedEmbreeDevice(), RTC_GEOMETRY_TYPE_TRIANGLE);
  if (!geom) return EmbreeFailure("rtcNewGeometry(triangles)");
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, impl->vertex_data.data(), 0,
                             3 * sizeof(float), nv);
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, impl->faces.data(), 0,
                             sizeof(Eigen::Vector3i), mesh.faces.size());
  SEMVOX_RETURN_IF_ERROR(CommitScene(geom, options.robust, impl.get(), "triangle mesh"));
  return Raycaster(std::move(impl));
}

Result<Raycaster> Raycaster::FromCloud(const PointCloud& cloud, const RaycasterOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("render options: " + error);
  const size_t n = cloud.points.size();
  if (n < 3) return Status::InvalidInput("point cloud has " + std::to_string(n) + " points; at least 3 are needed to render it");
  if (!SharedEmbreeDevice()) return EmbreeFailure("rtcNewDevice");
  for (size_t i = 0; i < n; ++i)
    if (!cloud.points[i].allFinite())
      return Status::InvalidInput("cloud point " + std::to_string(i) + " is not finite (hint: load through LoadScene, which drops them)");
  const bool own_normals = cloud.normals.size() == n;
  auto impl = std::make_unique<Impl>();
  impl->is_cloud = true;
  impl->num_primitives = n;
  // The discs: one per point, or one per occupied cell of cloud_cell_m.
  const PointCloud* discs = &cloud;
  PointCloud merged;
  if (options.cloud_cell_m > 0) {
    MergedCloud m = MergeCloudCells(cloud, options.cloud_cell_m);
    merged = std::move(m.cloud);
    impl->disc_point = std::move(m.representative);
    discs = &merged;
  }
  const size_t nd = discs->points.size();
  const CloudGeometry local = EstimateCloudGeometry(*discs, options.spacing_neighbors);
  impl->vertex_data.resize(4 * nd + 1, 0.0f);
  impl->normal_data.resize(3 * nd + 1, 0.0f);
  impl->radii.resize(nd);
  for (size_t i = 0; i < nd; ++i) {
    const Eigen::Vector3f& p = discs->points[i];
    Eigen::Vector3f nrm = own_normals ? discs->normals[i] : local.normals[i];
    if (!nrm.allFinite() || nrm.squaredNorm() < 1e-12f) nrm = Eigen::Vector3f::UnitZ();
    nrm.normalize();
    const float spacing = local.spacing[i];
    const float radius = float(options.point_radius_factor) * (std::isfinite(spacing) && spacing > 0 ? spacing : 1e-3f);
    impl->radii[i] = radius;
    impl->vertex_data[4 * i + 0] = p.x();
    impl->vertex_data[4 * i + 1] = p.y();
    impl->vertex_data[4 * i + 2] = p.z();
    impl->vertex_data[4 * i + 3] = radius;
    std::memcpy(&impl->normal_data[3 * i], nrm.data(), 3 * sizeof(float));
  }
  if (options.cloud_squares) {
    // Two triangles per disc: the square of half side `radius` in the disc's plane. Triangles of one square
    // report the disc's index (primID / 2); their barycentrics are not used for clouds.
    std::vector<float> corners(3 * 4 * nd + 1, 0.0f);
    impl->faces.resize(2 * nd + 1);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, nd, 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const Eigen::Vector3f c(impl->vertex_data[4 * i], impl->vertex_data[4 * i + 1], impl->vertex_data[4 * i + 2]);
        const Eigen::Vector3f nrm(impl->normal_data[3 * i], impl->normal_data[3 * i + 1], impl->normal_data[3 * i + 2]);
        const Eigen::Vector3f a = std::abs(nrm.x()) < 0.9f ? Eigen::Vector3f::UnitX() : Eigen::Vector3f::UnitY();
        const Eigen::Vector3f t1 = nrm.cross(a).normalized() * impl->radii[i], t2 = nrm.cross(t1);
        const Eigen::Vector3f v[4] = {c - t1 - t2, c + t1 - t2, c + t1 + t2, c - t1 + t2};
        for (int k = 0; k < 4; ++k) std::memcpy(&corners[3 * (4 * i + size_t(k))], v[k].data(), 3 * sizeof(float));
        const int b = int(4 * i);
        impl->faces[2 * i] = Eigen::Vector3i(b, b + 1, b + 2);
        impl->faces[2 * i + 1] = Eigen::Vector3i(b, b + 2, b + 3);
      }
    });
    impl->vertex_data = std::move(corners);
    impl->squares = true;
    RTCGeometry tri = rtcNewGeometry(SharedEmbreeDevice(), RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!tri) return EmbreeFailure("rtcNewGeometry(cloud squares)");
    rtcSetSharedGeometryBuffer(tri, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, impl->vertex_data.data(), 0, 3 * sizeof(float), 4 * nd);
    rtcSetSharedGeometryBuffer(tri, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, impl->faces.data(), 0, sizeof(Eigen::Vector3i), 2 * nd);
    // Not Embree's watertight test: it keeps rays from slipping between faces that share an edge, and the
    // squares overlap their neighbours anyway (a quarter of the trace time at 160 x 120, the same hits on
    // the 91 m2 flat of seed 106: cloud_render_bench, docs/speed.md).
    SEMVOX_RETURN_IF_ERROR(CommitScene(tri, /*robust=*/false, impl.get(), "point cloud squares"));
    // Primitive of triangle t: disc t / 2, then its point.
    std::vector<int32_t> tri_point(2 * nd);
    for (size_t t = 0; t < 2 * nd; ++t) tri_point[t] = impl->disc_point.empty() ? int32_t(t / 2) : impl->disc_point[t / 2];
    impl->disc_point = std::move(tri_point);
    return Raycaster(std::move(impl));
  }
  RTCGeometry geom = rtcNewGeometry(SharedEmbreeDevice(), RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT);
  if (!geom) return EmbreeFailure("rtcNewGeometry(oriented discs)");
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, impl->vertex_data.data(), 0,
                             4 * sizeof(float), nd);
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, impl->normal_data.data(), 0,
                             3 * sizeof(float), nd);
  SEMVOX_RETURN_IF_ERROR(CommitScene(geom, options.robust, impl.get(), "point cloud"));
  return Raycaster(std::move(impl));
}

Result<Raycaster> Raycaster::FromScene(const Scene& scene, const RaycasterOptions& options) {
  return scene.is_mesh() ? FromMesh(scene.mesh, options) : FromCloud(scene.cloud, options);
}

RayHit Raycaster::Intersect(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = ray.origin.x();
  rh.ray.org_y = ray.origin.y();
  rh.ray.org_z = ray.origin.z();
  rh.ray.dir_x = ray.direction.x();
  rh.ray.dir_y = ray.direction.y();
  rh.ray.dir_z = ray.direction.z();
  rh.ray.tnear = ray.t_min;
  rh.ray.tfar = ray.t_max;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  RayHit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.distance = rh.ray.tfar;
  h.primitive = impl_->disc_point.empty() ? int32_t(rh.hit.primID) : impl_->disc_point[rh.hit.primID];
  h.u = impl_->is_cloud ? 0.0f : rh.hit.u;
  h.v = impl_->is_cloud ? 0.0f : rh.hit.v;
  Eigen::Vector3f n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  const float len = n.norm();
  n = len > 0 ? Eigen::Vector3f(n / len) : Eigen::Vector3f(-ray.direction.normalized());
  if (n.dot(ray.direction) > 0) n = -n;
  h.normal = n;
  return h;
}

void Raycaster::IntersectSerial(std::span<const Ray> rays, std::span<RayHit> hits) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(64) RTCRayHit16 packet;
  alignas(64) int valid[16];
  for (size_t begin = 0; begin < rays.size(); begin += 16) {
    const int count = int(std::min<size_t>(16, rays.size() - begin));
    for (int lane = 0; lane < 16; ++lane) {
      valid[lane] = lane < count ? -1 : 0;
      SetPacketRay(packet, lane, rays[begin + std::min(lane, count - 1)]);
    }
    rtcIntersect16(valid, impl_->scene, &context, &packet);
    for (int lane = 0; lane < count; ++lane) {
      hits[begin + lane] = ToHit(packet, lane, impl_->disc_point);
      if (impl_->is_cloud) hits[begin + lane].u = hits[begin + lane].v = 0.0f;
    }
  }
}

void Raycaster::Intersect(std::span<const Ray> rays, std::vector<RayHit>* hits) const {
  hits->resize(rays.size());
  constexpr size_t kRaysPerTask = 16 * 64;
  const size_t tasks = (rays.size() + kRaysPerTask - 1) / kRaysPerTask;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tasks), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t t = r.begin(); t != r.end(); ++t) {
      const size_t begin = t * kRaysPerTask;
      const size_t count = std::min(kRaysPerTask, rays.size() - begin);
      IntersectSerial(rays.subspan(begin, count), std::span<RayHit>(hits->data() + begin, count));
    }
  });
}

Eigen::Vector3d Raycaster::HitPoint(const Ray& ray, const RayHit& hit) const {
  if (!impl_->is_cloud && hit.primitive >= 0 && size_t(hit.primitive) < impl_->num_primitives)
    return impl_->MeshPoint(hit.primitive, hit.u, hit.v);
  return ray.origin.cast<double>() + double(hit.distance) * ray.direction.cast<double>();
}

}  // namespace semvox
