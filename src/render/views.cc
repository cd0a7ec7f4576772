#include "render/views.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iomanip>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>

#include <tbb/parallel_pipeline.h>

#include "core/log.h"
#include "render/view_selection.h"

namespace semvox {
namespace {

// "Infinite" distance for cells with no obstacle in reach; finite so the parabola algebra stays exact.
constexpr double kFar = 1e20;

// Squared Euclidean distance transform of a 1-D function (Felzenszwalb & Huttenlocher, "Distance
// Transforms of Sampled Functions", Theory of Computing 2012, Algorithm 1): d[q] = min_p (q - p)^2 + f[p].
void Edt1d(const std::vector<double>& f, std::vector<double>* d, std::vector<int>* v, std::vector<double>* z) {
  const int n = int(f.size());
  int k = 0;
  (*v)[0] = 0;
  (*z)[0] = -std::numeric_limits<double>::infinity();
  (*z)[1] = std::numeric_limits<double>::infinity();
  for (int q = 1; q < n; ++q) {
    const auto meet = [&](int p) { return ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * q - 2.0 * p); };
    double s = meet((*v)[k]);
    while (s <= (*z)[k]) s = meet((*v)[--k]);  // Terminates: z[0] = -infinity.
    ++k;
    (*v)[k] = q;
    (*z)[k] = s;
    (*z)[k + 1] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while ((*z)[k + 1] < q) ++k;
    const int p = (*v)[k];
    (*d)[q] = std::min(kFar, double(q - p) * (q - p) + f[p]);
  }
}

// Squared distance, in cells, from every cell of an nx x ny layer to the nearest obstacle cell.
std::vector<double> SquaredDistanceToObstacles(const std::vector<uint8_t>& obstacle, int nx, int ny) {
  std::vector<double> dist(size_t(nx) * ny);
  const int n = std::max(nx, ny);
  std::vector<double> f(n), d(n), z(n + 1);
  std::vector<int> v(n);
  f.resize(ny), d.resize(ny);
  for (int x = 0; x < nx; ++x) {  // Columns.
    for (int y = 0; y < ny; ++y) f[y] = obstacle[size_t(y) * nx + x] ? 0.0 : kFar;
    Edt1d(f, &d, &v, &z);
    for (int y = 0; y < ny; ++y) dist[size_t(y) * nx + x] = d[y];
  }
  f.resize(nx), d.resize(nx);
  for (int y = 0; y < ny; ++y) {  // Rows.
    for (int x = 0; x < nx; ++x) f[x] = dist[size_t(y) * nx + x];
    Edt1d(f, &d, &v, &z);
    for (int x = 0; x < nx; ++x) dist[size_t(y) * nx + x] = d[x];
  }
  return dist;
}

double ViewHeight(const VoxelMap& map, const ViewsOptions& options) {
  if (map.floor_found && map.ceiling_found && map.ceiling_z > map.floor_z)
    return map.floor_z + options.height_fraction * (map.ceiling_z - map.floor_z);
  if (!map.scan_positions.empty()) {
    double z = 0;
    for (const auto& p : map.scan_positions) z += p.z();
    z /= double(map.scan_positions.size());
    // Fused RGB-D scans rarely hold their ceiling (ScanNet's never do), so say which one is missing and where
    // the cameras went.
    const bool floor = map.floor_found;
    SEMVOX_WARN("views: " << (floor ? "no ceiling found" : map.ceiling_found ? "no floor found" : "no floor or ceiling found")
                          << "; cameras placed at the height of the virtual scan positions, " << std::fixed << std::setprecision(2)
                          << (floor ? "" : "z = ") << (floor ? z - map.floor_z : z) << (floor ? " m above the floor" : " m"));
    return z;
  }
  const Eigen::Vector3d lo = map.grid.MinCorner();
  return lo.z() + 0.5 * map.grid.dims()[2] * map.grid.resolution();
}

}  // namespace

const char* ViewDropName(ViewDrop d) {
  switch (d) {
    case ViewDrop::kKept: return "kept";
    case ViewDrop::kEmpty: return "empty";
    case ViewDrop::kTooClose: return "too_close";
    case ViewDrop::kHomogeneous: return "homogeneous";
  }
  return "?";
}

bool ViewsOptions::Check(std::string* error) const {
  if (!CheckOptions(*this, Options(), error)) return false;
  const auto divides_360 = [](double step) { return std::abs(360.0 / step - std::round(360.0 / step)) <= 1e-6; };
  std::ostringstream os;
  if (!divides_360(yaw_step_deg)) os << "yaw_step_deg = " << yaw_step_deg << ". Violated constraint: yaw_step_deg divides 360";
  else if (!divides_360(tilted_ring_yaw_step_deg))
    os << "tilted_ring_yaw_step_deg = " << tilted_ring_yaw_step_deg
       << ". Violated constraint: tilted_ring_yaw_step_deg divides 360";
  else if (std::abs(pitch_deg) + tilted_ring_deg > 89)
    os << "tilted_ring_deg = " << tilted_ring_deg << ". Violated constraint: -89 <= pitch_deg +- tilted_ring_deg <= 89 "
       << "(pitch_deg = " << pitch_deg << ")";
  if (os.str().empty()) return true;
  if (error) *error = os.str();
  return false;
}

size_t ViewSet::num_kept() const {
  return size_t(std::count_if(views.begin(), views.end(), [](const ViewRecord& v) { return v.kept(); }));
}

std::vector<Eigen::Vector3d> PlaceViewpoints(const VoxelMap& map, const ViewsOptions& options, double* view_z) {
  const VoxelGrid& grid = map.grid;
  const double z = ViewHeight(map, options);
  if (view_z) *view_z = z;
  std::vector<Eigen::Vector3d> positions;
  const int nx = grid.dims()[0], ny = grid.dims()[1];
  if (grid.size() == 0) return positions;
  const int iz = grid.CellOf(Eigen::Vector3d(0, 0, z))[2];
  if (iz < 0 || iz >= grid.dims()[2]) return positions;

  // Mid-height layer: distance from every free voxel to the nearest voxel that is not free.
  std::vector<uint8_t> obstacle(size_t(nx) * ny);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x)
      obstacle[size_t(y) * nx + x] = grid.state(grid.Index(x, y, iz)) != VoxelState::kFree;
  const std::vector<double> d2 = SquaredDistanceToObstacles(obstacle, nx, ny);
  const double res = grid.resolution();
  // A voxel centre is clear when every non-free voxel's centre is at least clearance + half a voxel
  // diagonal away, so that no point of a non-free voxel is nearer than the clearance.
  const double min_cells = options.wall_clearance_m / res + 0.5 * std::numbers::sqrt2;

  // One viewpoint per grid_spacing_m square: the clear voxel nearest the square's centre. The squares start at
  // the grid's lower corner, so one scan in two poses gets the same viewpoints relative to its walls (the
  // canonical frame puts both on the same grid up to whole voxels; world multiples of the spacing would not).
  struct Best {
    double dist2;
    Eigen::Vector3d p;
  };
  std::map<std::pair<int64_t, int64_t>, Best> best;
  const double s = options.grid_spacing_m;
  const Eigen::Vector3d corner = grid.CellCenter(0, 0, iz) - Eigen::Vector3d(0.5 * res, 0.5 * res, 0);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const size_t i = size_t(y) * nx + x;
      if (obstacle[i] || d2[i] < min_cells * min_cells) continue;
      const Eigen::Vector3d c = grid.CellCenter(x, y, iz);
      const int64_t sx = int64_t(std::floor((c.x() - corner.x()) / s)), sy = int64_t(std::floor((c.y() - corner.y()) / s));
      const Eigen::Vector2d centre(corner.x() + (sx + 0.5) * s, corner.y() + (sy + 0.5) * s);
      const double dc = (c.head<2>() - centre).squaredNorm();
      auto [it, inserted] = best.try_emplace({sy, sx}, Best{dc, Eigen::Vector3d(c.x(), c.y(), z)});
      if (!inserted && dc < it->second.dist2) it->second = Best{dc, Eigen::Vector3d(c.x(), c.y(), z)};
    }
  for (const auto& [square, b] : best) positions.push_back(b.p);
  return positions;
}

namespace {

// MeasureView's depth buffer, kept per thread between views.
std::vector<float>& MeasureScratch() {
  thread_local std::vector<float> depths;
  return depths;
}

}  // namespace

// The k-th smallest of `values` (k < size; the order of `values` is lost), as std::nth_element finds it.
// Non-negative floats order as their bit patterns: a histogram of the top 16 bits finds the bucket that
// holds the k-th value, and nth_element runs on that bucket alone. Negative or NaN values: nth_element.
float NthSmallest(std::vector<float>* values, size_t k) {
  std::vector<float>& v = *values;
  std::vector<uint32_t> count(size_t(1) << 16, 0);
  for (float x : v) {
    if (!(x >= 0.0f)) {
      std::nth_element(v.begin(), v.begin() + ptrdiff_t(k), v.end());
      return v[k];
    }
    uint32_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    ++count[bits >> 16];
  }
  uint32_t bucket = 0;
  size_t below = 0;
  while (below + count[bucket] <= k) below += count[bucket++];
  size_t m = 0;
  for (float x : v) {  // The bucket's values to the front (in place: v is scratch).
    uint32_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    if ((bits >> 16) == bucket) v[m++] = x;
  }
  std::nth_element(v.begin(), v.begin() + ptrdiff_t(k - below), v.begin() + ptrdiff_t(m));
  return v[k - below];
}

void MeasureView(const RenderedView& view, const ViewsOptions& options, ViewRecord* record) {
  const size_t n = view.depth.data.size();
  std::vector<float>& depths = MeasureScratch();
  depths.clear();
  depths.reserve(view.hit_pixels);
  // The colour sums in integers: exact, so their doubles are those of summing the doubles pixel by pixel
  // (every partial sum is an integer below 2^53).
  uint64_t sum_int[3] = {0, 0, 0}, sum2_int[3] = {0, 0, 0};
  for (size_t i = 0; i < n; ++i) {
    if (view.primitive.data[i] < 0) continue;
    depths.push_back(view.depth.data[i]);
    for (int c = 0; c < 3; ++c) {
      const uint64_t v = view.rgb.data[3 * i + c];
      sum_int[c] += v;
      sum2_int[c] += v * v;
    }
  }
  double sum[3], sum2[3];
  for (int c = 0; c < 3; ++c) sum[c] = double(sum_int[c]), sum2[c] = double(sum2_int[c]);
  const size_t hits = depths.size();
  record->hit_fraction = n ? double(hits) / double(n) : 0.0;
  record->median_depth_m = 0;
  record->color_stddev = 0;
  if (hits > 0) {
    record->median_depth_m = NthSmallest(&depths, hits / 2);
    double var = 0;
    for (int c = 0; c < 3; ++c) {
      const double mean = sum[c] / double(hits);
      var += std::max(0.0, sum2[c] / double(hits) - mean * mean);
    }
    record->color_stddev = std::sqrt(var / 3.0);
  }
  if (hits == 0 || record->hit_fraction < options.min_hit_fraction) record->drop = ViewDrop::kEmpty;
  else if (record->median_depth_m < options.min_median_depth_m) record->drop = ViewDrop::kTooClose;
  else if (record->color_stddev < options.min_color_stddev) record->drop = ViewDrop::kHomogeneous;
  else record->drop = ViewDrop::kKept;
}

Result<ViewSet> RenderViews(const ViewRenderer& renderer, const VoxelMap& map, const ViewsOptions& options,
                            const ViewSink& sink) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("configuration: render." + error);
  ViewSet set;
  set.camera = options.Camera();
  set.voxel_size_m = map.grid.resolution();
  set.positions = PlaceViewpoints(map, options, &set.view_z);
  if (set.positions.empty()) {
    // Degraded scans (a single plane, no free space) still get their other outputs: no views, a warning.
    SEMVOX_WARN("views: no free voxel at camera height z = " << set.view_z << " is " << options.wall_clearance_m
                << " m from the nearest non-free voxel; no views rendered (lower render.wall_clearance_m, or check "
                   "that the scene is an enclosed interior)");
    set.voxel_seen.assign(map.grid.size(), 0);
    return set;
  }
  // (pitch, yaw step) of each ring: the main ring first, then the tilted ones.
  std::vector<std::pair<double, double>> rings{{options.pitch_deg, options.yaw_step_deg}};
  if (options.tilted_ring_deg > 0) {
    rings.push_back({options.pitch_deg - options.tilted_ring_deg, options.tilted_ring_yaw_step_deg});
    rings.push_back({options.pitch_deg + options.tilted_ring_deg, options.tilted_ring_yaw_step_deg});
  }
  const RenderOptions render = options.Render(map.grid.resolution());
  set.voxel_seen.assign(map.grid.size(), 0);
  // Every view in order: (position, pitch, yaw step, k).
  struct Pose {
    int position;
    double pitch, yaw;
  };
  std::vector<Pose> poses;
  for (size_t p = 0; p < set.positions.size(); ++p)
    for (const auto& [pitch, yaw_step] : rings)
      for (int k = 0; k < int(std::lround(360.0 / yaw_step)); ++k) poses.push_back({int(p), pitch, k * yaw_step});
  // Two stages, each serial and in view order: rendering (parallel over pixels inside) and what follows it
  // (the view's measures, the seen voxels, the sink). With a few views in flight, view k + 1 renders while
  // view k is measured and handed to the sink, so the serial parts of both overlap; the results are the
  // same as one view at a time.
  struct InFlight {
    ViewRecord record;
    RenderedView view;
  };
  constexpr size_t kInFlight = 3;
  std::vector<InFlight> slots(kInFlight);
  size_t next_pose = 0;
  double seconds = 0;
  Status render_error = Status::Ok(), sink_error = Status::Ok();
  std::atomic<bool> failed{false};
  tbb::parallel_pipeline(
      kInFlight,
      tbb::make_filter<void, InFlight*>(tbb::filter_mode::serial_in_order,
                                        [&](tbb::flow_control& fc) -> InFlight* {
                                          if (next_pose >= poses.size() || failed.load()) {
                                            fc.stop();
                                            return nullptr;
                                          }
                                          const size_t i = next_pose++;
                                          InFlight* slot = &slots[i % kInFlight];
                                          ViewRecord& r = slot->record;
                                          r = ViewRecord();
                                          r.id = int(i);
                                          r.position = poses[i].position;
                                          r.yaw_deg = poses[i].yaw;
                                          r.pitch_deg = poses[i].pitch;
                                          r.world_from_camera = WorldFromCameraYawPitch(set.positions[size_t(r.position)], r.yaw_deg, r.pitch_deg);
                                          const auto t0 = std::chrono::steady_clock::now();
                                          Status st = renderer.Render(set.camera, r.world_from_camera, render, &slot->view);
                                          seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                                          if (!st.ok()) {
                                            render_error = st;
                                            failed = true;
                                            fc.stop();
                                            return nullptr;
                                          }
                                          return slot;
                                        }) &
          tbb::make_filter<InFlight*, void>(tbb::filter_mode::serial_in_order, [&](InFlight* slot) {
            if (failed.load()) return;
            ViewRecord& r = slot->record;
            const RenderedView& view = slot->view;
            MeasureView(view, options, &r);
            if (r.kept()) {
              std::array<int, 3> cell;
              for (size_t i = 0; i < view.primitive.data.size(); ++i)
                if (view.primitive.data[i] >= 0 && map.grid.CellOfKey(view.voxel_key.data[i], &cell))
                  set.voxel_seen[map.grid.Index(cell[0], cell[1], cell[2])] = 1;
            }
            if (sink) {
              Status st = sink(r, view);
              if (!st.ok()) {
                sink_error = st;
                failed = true;
                return;
              }
            }
            set.views.push_back(r);
          }));
  SEMVOX_RETURN_IF_ERROR(render_error);
  SEMVOX_RETURN_IF_ERROR(sink_error);
  set.seconds_render = seconds;
  return set;
}

std::string ThumbnailName(int view_id) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "views/view_%05d.png", view_id);
  return buf;
}

std::string ViewsToJson(const ViewSet& set, const ViewsOptions& options, bool with_thumbnails,
                        const Eigen::Isometry3d& input_from_world) {
  using json = nlohmann::ordered_json;
  const bool identity = IsIdentity(input_from_world);
  auto point = [&](const Eigen::Vector3d& p) { return identity ? p : Eigen::Vector3d(input_from_world * p); };
  json j;
  j["conventions"] = {
      {"world", "input frame, metres, +Z up"},
      {"camera", "x right, y down, z forward (OpenCV); pixel (0,0) centre at (0.5, 0.5)"},
      {"world_from_camera", "4x4 row-major; maps camera coordinates to world coordinates"},
      {"yaw_deg", "about world +Z from +X towards +Y"},
      {"pitch_deg", "> 0 looks up"}};
  const PinholeCamera& c = set.camera;
  j["intrinsics"] = {{"model", "pinhole"}, {"width", c.width}, {"height", c.height}, {"fx", c.fx}, {"fy", c.fy},
                     {"cx", c.cx},         {"cy", c.cy},       {"horizontal_fov_deg", c.HorizontalFovDeg()},
                     {"vertical_fov_deg", c.VerticalFovDeg()}};
  j["voxel_size_m"] = set.voxel_size_m;
  j["camera_z"] = identity ? set.view_z : point(Eigen::Vector3d(0, 0, set.view_z)).z();
  j["filters"] = {{"min_hit_fraction", options.min_hit_fraction},
                  {"min_median_depth_m", options.min_median_depth_m},
                  {"min_color_stddev", options.min_color_stddev}};
  std::map<std::string, size_t> counts{{"kept", 0}, {"empty", 0}, {"too_close", 0}, {"homogeneous", 0}};
  for (const auto& v : set.views) ++counts[ViewDropName(v.drop)];
  j["counts"] = {{"positions", set.positions.size()}, {"views", set.views.size()}, {"kept", counts["kept"]},
                 {"dropped_empty", counts["empty"]}, {"dropped_too_close", counts["too_close"]},
                 {"dropped_homogeneous", counts["homogeneous"]}};
  json positions = json::array();
  for (const auto& q : set.positions) {
    const Eigen::Vector3d p = point(q.cast<double>());
    positions.push_back({p.x(), p.y(), p.z()});
  }
  j["positions"] = positions;
  json views = json::array();
  for (const auto& v : set.views) {
    json m = json::array();
    const Eigen::Matrix4d t = identity ? Eigen::Matrix4d(v.world_from_camera.matrix())
                                       : Eigen::Matrix4d(input_from_world.matrix() * v.world_from_camera.matrix());
    for (int r = 0; r < 4; ++r) m.push_back({t(r, 0), t(r, 1), t(r, 2), t(r, 3)});
    double yaw_deg = v.yaw_deg, pitch_deg = v.pitch_deg;
    if (!identity) {  // From the optical axis (camera +z) in the input frame.
      const Eigen::Vector3d f = t.block<3, 1>(0, 2);
      yaw_deg = std::atan2(f.y(), f.x()) * 180.0 / M_PI;
      if (yaw_deg < 0) yaw_deg += 360.0;  // [0, 360) as the views' own yaws.
      pitch_deg = std::asin(std::clamp(f.z(), -1.0, 1.0)) * 180.0 / M_PI;
    }
    json e = {{"id", v.id},
              {"position", v.position},
              {"yaw_deg", yaw_deg},
              {"pitch_deg", pitch_deg},
              {"world_from_camera", m},
              {"kept", v.kept()},
              {"drop_reason", v.kept() ? "" : ViewDropName(v.drop)},
              {"hit_fraction", v.hit_fraction},
              {"median_depth_m", v.median_depth_m},
              {"color_stddev", v.color_stddev}};
    if (with_thumbnails) e["thumbnail"] = ThumbnailName(v.id);
    views.push_back(e);
  }
  j["views"] = views;
  return j.dump(1) + "\n";
}

SurfaceCoverage ComputeSurfaceCoverage(const VoxelGrid& grid, const std::vector<uint8_t>& voxel_seen) {
  SurfaceCoverage cov;
  const std::vector<uint32_t> surface = SurfaceVoxels(grid);
  cov.surface_voxels = surface.size();
  for (uint32_t i : surface) cov.seen_voxels += i < voxel_seen.size() && voxel_seen[i];
  return cov;
}

}  // namespace semvox
