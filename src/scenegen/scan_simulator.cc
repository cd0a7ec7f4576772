#include "scenegen/scan_simulator.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <sstream>
#include <unordered_map>

#include "core/labels.h"
#include "render/raycaster.h"
#include "scenegen/random.h"

namespace semvox {

bool ScanSimulationOptions::Check(std::string* error) const {
  std::ostringstream os;
  if (!(station_spacing_m > 0)) os << "station_spacing_m = " << station_spacing_m << ". Violated constraint: > 0";
  else if (!(station_clearance_m >= 0)) os << "station_clearance_m = " << station_clearance_m << ". Violated constraint: >= 0";
  else if (!(scanner_height_m > 0)) os << "scanner_height_m = " << scanner_height_m << ". Violated constraint: > 0";
  else if (azimuth_steps < 8) os << "azimuth_steps = " << azimuth_steps << ". Violated constraint: >= 8";
  else if (elevation_steps < 4) os << "elevation_steps = " << elevation_steps << ". Violated constraint: >= 4";
  else if (!(min_range_m >= 0 && max_range_m > min_range_m))
    os << "min_range_m = " << min_range_m << ", max_range_m = " << max_range_m
       << ". Violated constraint: 0 <= min_range_m < max_range_m";
  else if (!(noise_sigma_m >= 0 && noise_quadratic >= 0))
    os << "noise_sigma_m = " << noise_sigma_m << ", noise_quadratic = " << noise_quadratic << ". Violated constraint: both >= 0";
  else if (!(fuse_voxel_m > 0)) os << "fuse_voxel_m = " << fuse_voxel_m << ". Violated constraint: > 0";
  if (os.str().empty()) return true;
  if (error) *error = os.str();
  return false;
}

namespace {

// True when (x, y) keeps `clearance` from every furniture part standing below `height`.
bool StationIsFree(const Apartment& apt, double x, double y, double clearance, double height) {
  using namespace nyu40;
  for (const SolidPart& p : apt.parts) {
    if (p.structural || p.label == kFloorMat || p.label == kWindow) continue;
    const OrientedBox& b = p.box;
    if (b.center.z() - b.size.z() / 2 > height) continue;
    const double c = std::cos(b.yaw_rad), s = std::sin(b.yaw_rad);
    const double dx = x - b.center.x(), dy = y - b.center.y();
    const double lx = c * dx + s * dy, ly = -s * dx + c * dy;
    if (std::fabs(lx) <= b.size.x() / 2 + clearance && std::fabs(ly) <= b.size.y() / 2 + clearance) return false;
  }
  return true;
}

}  // namespace

std::vector<Eigen::Vector3d> ScanStations(const Apartment& apt, const ScanSimulationOptions& o) {
  // Rooms in breadth-first order over the doors and open-plan links, from the entrance.
  const int n = int(apt.rooms.size());
  std::vector<std::vector<int>> adj(size_t(n) + 1);
  int start = 1;
  for (const DoorGt& d : apt.doors) {
    if (d.room_b < 0) start = d.room_a;
    else adj[size_t(d.room_a)].push_back(d.room_b), adj[size_t(d.room_b)].push_back(d.room_a);
  }
  for (const RoomGt& r : apt.rooms)
    for (int other : r.open_to) adj[size_t(r.id)].push_back(other);
  std::vector<int> order;
  std::vector<bool> seen(size_t(n) + 1, false);
  std::deque<int> queue{start};
  seen[size_t(start)] = true;
  while (!queue.empty()) {
    const int r = queue.front();
    queue.pop_front();
    order.push_back(r);
    for (int nb : adj[size_t(r)])
      if (!seen[size_t(nb)]) seen[size_t(nb)] = true, queue.push_back(nb);
  }
  for (int r = 1; r <= n; ++r)
    if (!seen[size_t(r)]) order.push_back(r);

  const double z = apt.floor_z_m + std::min(o.scanner_height_m, apt.ceiling_z_m - apt.floor_z_m - 0.2);
  const double reach = o.scanner_height_m + 0.3;
  std::vector<Eigen::Vector3d> stations;
  for (int id : order) {
    const RoomGt& r = apt.rooms[size_t(id - 1)];
    // A room that is not its box (plan apartments): the station must stand on the room's own floor.
    auto in_room = [&](double x, double y) { return apt.room_raster.data.empty() || RoomIdAt(apt, x, y) == id; };
    const double m = o.station_clearance_m;
    const double w = r.x1 - r.x0 - 2 * m, h = r.y1 - r.y0 - 2 * m;
    if (w <= 0 || h <= 0) continue;
    const int nx = std::max(1, int(std::lround(w / o.station_spacing_m))), ny = std::max(1, int(std::lround(h / o.station_spacing_m)));
    size_t before = stations.size();
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int ii = (j % 2) ? nx - 1 - i : i;  // Serpentine walk.
        const double x = r.x0 + m + (ii + 0.5) * w / nx, y = r.y0 + m + (j + 0.5) * h / ny;
        if (in_room(x, y) && StationIsFree(apt, x, y, m, reach)) stations.emplace_back(x, y, z);
      }
    if (stations.size() > before) continue;
    // No grid station is free: the free spot nearest the room centre on a 0.1 m grid.
    const double cx = 0.5 * (r.x0 + r.x1), cy = 0.5 * (r.y0 + r.y1);
    double best = 1e18;
    Eigen::Vector3d best_p;
    for (double y = r.y0 + m; y <= r.y1 - m; y += 0.1)
      for (double x = r.x0 + m; x <= r.x1 - m; x += 0.1) {
        const double d = (x - cx) * (x - cx) + (y - cy) * (y - cy);
        if (d < best && in_room(x, y) && StationIsFree(apt, x, y, m, reach)) best = d, best_p = Eigen::Vector3d(x, y, z);
      }
    if (best < 1e18) stations.push_back(best_p);
  }
  return stations;
}

Result<PointCloud> SimulateScan(const Apartment& apt, const ScanSimulationOptions& o) {
  std::string error;
  if (!o.Check(&error)) return Status::InvalidInput("scan simulation options: " + error);
  Result<Raycaster> rc = Raycaster::FromMesh(apt.mesh);
  if (!rc.ok()) return rc.status();
  const std::vector<Eigen::Vector3d> stations = ScanStations(apt, o);
  if (stations.empty()) return Status::Internal("scan simulation: no free scanner station in any room");
  Rng rng(SplitMix64(o.seed ^ 0x5ca9ULL));
  const Mesh& mesh = apt.mesh;
  const auto& label = mesh.face_attributes.at("label");
  const auto& instance = mesh.face_attributes.at("instance");
  const auto& room = mesh.face_attributes.at("room");
  PointCloud cloud;
  auto& out_label = cloud.point_attributes["label"];
  auto& out_instance = cloud.point_attributes["instance"];
  auto& out_room = cloud.point_attributes["room"];
  std::unordered_map<uint64_t, uint32_t> fused;
  const double inv = 1.0 / o.fuse_voxel_m;
  std::vector<Ray> rays;
  std::vector<RayHit> hits;
  for (const Eigen::Vector3d& s : stations) {
    rays.clear();
    const double az0 = rng.Uniform(0, 2 * M_PI);
    for (int e = 0; e < o.elevation_steps; ++e) {
      // Equal-area rows: sin(elevation) uniform in (-1, 1).
      const double sz = -1.0 + (e + rng.Uniform(0.25, 0.75)) * 2.0 / o.elevation_steps;
      const double cz = std::sqrt(std::max(0.0, 1 - sz * sz));
      const int steps = std::max(1, int(std::lround(o.azimuth_steps * cz)));
      for (int a = 0; a < steps; ++a) {
        const double az = az0 + (a + rng.Uniform(0.0, 1.0)) * 2 * M_PI / steps;
        Ray ray;
        ray.origin = s.cast<float>();
        ray.direction = Eigen::Vector3f(float(cz * std::cos(az)), float(cz * std::sin(az)), float(sz));
        ray.t_min = float(o.min_range_m);
        ray.t_max = float(o.max_range_m);
        rays.push_back(ray);
      }
    }
    rc->Intersect(rays, &hits);
    for (size_t i = 0; i < rays.size(); ++i) {
      const RayHit& h = hits[i];
      if (!h.hit()) continue;
      const double r = h.distance;
      const double sigma = o.noise_sigma_m + o.noise_quadratic * r * r;
      const double noisy = std::max(o.min_range_m, r + rng.Normal(0, sigma));
      const Eigen::Vector3d p = s + noisy * rays[i].direction.cast<double>();
      const uint64_t key = (uint64_t(uint32_t(int32_t(std::floor(p.x() * inv))) & 0x1fffff) << 42) |
                           (uint64_t(uint32_t(int32_t(std::floor(p.y() * inv))) & 0x1fffff) << 21) |
                           (uint64_t(uint32_t(int32_t(std::floor(p.z() * inv))) & 0x1fffff));
      if (!fused.emplace(key, uint32_t(cloud.points.size())).second) continue;
      const size_t f = size_t(h.primitive);
      cloud.points.push_back(p.cast<float>());
      cloud.normals.push_back(h.normal);
      cloud.colors.push_back(mesh.ColorAt(int(f), h.u, h.v));
      out_label.push_back(label[f]);
      out_instance.push_back(instance[f]);
      out_room.push_back(room[f]);
    }
  }
  return cloud;
}

}  // namespace semvox
