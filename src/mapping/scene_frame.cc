#include "mapping/scene_frame.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "mapping/cloud_geometry.h"
#include "mapping/voxelizer.h"

namespace semvox {
namespace {

constexpr double kDeg = M_PI / 180.0;

// One surface element: unit normal, position and weight (area in m², or spacing² for cloud points).
struct Samples {
  std::vector<Eigen::Vector3d> normal, position;
  std::vector<double> weight;
  bool oriented = false;  // Normals carry a meaningful sign (mesh winding).
  double total = 0;       // Sum of weights.
  size_t size() const { return weight.size(); }
};

Samples MeshSamples(const Mesh& mesh) {
  Samples s;
  const size_t n = mesh.faces.size();
  s.normal.assign(n, Eigen::Vector3d::Zero());
  s.position.assign(n, Eigen::Vector3d::Zero());
  s.weight.assign(n, 0.0);
  s.oriented = true;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t f = r.begin(); f != r.end(); ++f) {
      const Eigen::Vector3i& t = mesh.faces[f];
      const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>(), b = mesh.vertices[t[1]].cast<double>(),
                            c = mesh.vertices[t[2]].cast<double>();
      const Eigen::Vector3d cr = (b - a).cross(c - a);
      const double len = cr.norm();
      if (!(len > 0) || !std::isfinite(len)) continue;  // Degenerate: weight 0.
      s.normal[f] = cr / len;
      s.position[f] = (a + b + c) / 3.0;
      s.weight[f] = 0.5 * len;
    }
  });
  for (double w : s.weight) s.total += w;
  return s;
}

Samples CloudSamples(const PointCloud& cloud, const SceneFrameOptions& options) {
  Samples s;
  const size_t n = cloud.points.size();
  const size_t stride = std::max<size_t>(1, (n + options.max_cloud_points - 1) / std::max<size_t>(1, options.max_cloud_points));
  PointCloud sub;
  for (size_t i = 0; i < n; i += stride) {
    sub.points.push_back(cloud.points[i]);
    if (!cloud.normals.empty()) sub.normals.push_back(cloud.normals[i]);
  }
  const CloudGeometry geo = EstimateCloudGeometry(sub, options.cloud_normal_neighbors);
  const std::vector<Eigen::Vector3f>& normals = sub.normals.empty() ? geo.normals : sub.normals;
  const size_t m = sub.points.size();
  s.normal.resize(m);
  s.position.resize(m);
  s.weight.resize(m);
  for (size_t i = 0; i < m; ++i) {
    const Eigen::Vector3d nd = normals[i].cast<double>();
    const double len = nd.norm();
    s.normal[i] = len > 0 ? Eigen::Vector3d(nd / len) : Eigen::Vector3d::UnitZ();
    s.position[i] = sub.points[i].cast<double>();
    const double sp = std::max<double>(geo.spacing[i], 1e-3);
    s.weight[i] = len > 0 ? sp * sp : 0.0;
    s.total += s.weight[i];
  }
  s.oriented = false;  // PCA normals and most scanners' normals carry no reliable sign.
  return s;
}

// Refines an axis (unit, sign-free) to the weighted mean of the sample normals within `radius_rad` of it,
// each folded onto its side. Returns the weight within the final radius.
double RefineAxis(const Samples& s, double radius_rad, Eigen::Vector3d* axis) {
  const double cos_r = std::cos(radius_rad);
  double inside = 0;
  for (int it = 0; it < 4; ++it) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    inside = 0;
    for (size_t i = 0; i < s.size(); ++i) {
      const double d = s.normal[i].dot(*axis);
      if (std::fabs(d) < cos_r || s.weight[i] <= 0) continue;
      sum += (d < 0 ? -s.weight[i] : s.weight[i]) * s.normal[i];
      inside += s.weight[i];
    }
    if (!(sum.norm() > 0)) break;
    *axis = sum.normalized();
  }
  return inside;
}

// The dominant sign-free normal direction within `cone_rad` of +Z (as a unit vector with z > 0): peak of an
// area-weighted histogram of the folded normals' (x, y) in 0.5-degree bins, smoothed over 3 x 3 bins, then
// refined. Returns false when no sample lies in the cone.
bool DominantAxisNearZ(const Samples& s, double cone_rad, double refine_rad, Eigen::Vector3d* axis, double* weight) {
  const double r = std::sin(cone_rad), cos_c = std::cos(cone_rad);
  const double bin = std::sin(0.5 * kDeg);
  const int nb = int(std::ceil(2 * r / bin)) + 1;
  std::vector<double> hist(size_t(nb) * nb, 0.0);
  bool any = false;
  for (size_t i = 0; i < s.size(); ++i) {
    Eigen::Vector3d n = s.normal[i];
    if (std::fabs(n.z()) < cos_c || s.weight[i] <= 0) continue;
    if (n.z() < 0) n = -n;
    const int bx = std::clamp(int((n.x() + r) / bin), 0, nb - 1), by = std::clamp(int((n.y() + r) / bin), 0, nb - 1);
    hist[size_t(by) * nb + bx] += s.weight[i];
    any = true;
  }
  if (!any) return false;
  double best = -1;
  int bbx = 0, bby = 0;
  for (int y = 0; y < nb; ++y)
    for (int x = 0; x < nb; ++x) {
      double v = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (x + dx >= 0 && x + dx < nb && y + dy >= 0 && y + dy < nb) v += hist[size_t(y + dy) * nb + x + dx];
      if (v > best) best = v, bbx = x, bby = y;
    }
  const double px = -r + (bbx + 0.5) * bin, py = -r + (bby + 0.5) * bin;
  *axis = Eigen::Vector3d(px, py, std::sqrt(std::max(0.0, 1.0 - px * px - py * py))).normalized();
  *weight = RefineAxis(s, refine_rad, axis);
  if (axis->z() < 0) *axis = -*axis;
  return true;
}

// Whether the floor lies on the +axis side of the scan (up = -axis): furniture tops, seats and table
// undersides lie in the lower half between the lowest and highest horizontal planes, and the floor is the
// larger of those two planes. The first vote needs the two planes to be floor and ceiling: when they lie
// less than kMinCeilingHeight apart and one holds under a third of the other's area, the smaller is a
// furniture top (a single RGB-D view of a bed, a scan without its ceiling), furniture fills the half next to
// it as a matter of course, and only the second vote counts. A low room whose ceiling outweighs the floor
// that its furniture hides keeps both votes.
// Face orientation cannot tell: a turned room still has its normals pointing inwards (closed meshes) or
// towards the scanner.
constexpr double kMinCeilingHeight = 2.0;  // Metres: rooms are at least this high.
bool LooksUpsideDown(const Samples& s, const Eigen::Vector3d& axis, double horizontal_rad) {
  const double cos_h = std::cos(horizontal_rad);
  double wh = 0;
  std::vector<std::pair<double, double>> horizontal;  // (height along axis, weight)
  for (size_t i = 0; i < s.size(); ++i) {
    if (std::fabs(s.normal[i].dot(axis)) < cos_h || s.weight[i] <= 0) continue;
    horizontal.push_back({s.position[i].dot(axis), s.weight[i]});
    wh += s.weight[i];
  }
  if (wh <= 0) return false;
  // Weighted 1% and 99% height quantiles of the horizontal area: the lowest and highest planes.
  std::sort(horizontal.begin(), horizontal.end());
  auto quantile = [&](double q) {
    double acc = 0;
    for (const auto& [h, w] : horizontal)
      if ((acc += w) >= q * wh) return h;
    return horizontal.back().first;
  };
  const double lo = quantile(0.01), hi = quantile(0.99), mid = 0.5 * (lo + hi);
  double below = 0, above = 0, at_lo = 0, at_hi = 0;
  for (const auto& [h, w] : horizontal) {
    if (h < lo + 0.15) at_lo += w;  // The extreme planes themselves.
    else if (h > hi - 0.15) at_hi += w;
    else (h < mid ? below : above) += w;
  }
  // Two votes in [-1, 1], positive when the floor is at the low end: the furniture (tops, seats in the
  // lower half) and the extreme planes (the floor is the larger: fused clouds often miss the ceiling
  // wholly or in patches, and shelves and wall cabinets high up then outweigh the furniture below).
  auto vote = [](double a, double b) { return a + b > 0 ? (a - b) / (a + b) : 0.0; };
  const bool floor_and_ceiling = hi - lo >= kMinCeilingHeight || 3 * std::min(at_lo, at_hi) >= std::max(at_lo, at_hi);
  const double furniture = floor_and_ceiling ? vote(below, above) : 0.0;
  return furniture + vote(at_lo, at_hi) < 0;
}

// Wall direction modulo 90 degrees in the levelled frame, (-45, 45] degrees: peak of the area-weighted
// histogram of near-horizontal normals' azimuth modulo 90 (0.25-degree bins, smoothed over +-1 degree),
// refined by the circular mean of 4 x azimuth within 3 degrees. False when the walls carry too little area
// or no direction dominates.
bool WallYaw(const Samples& s, const Eigen::Matrix3d& level, const SceneFrameOptions& o, double* yaw_deg) {
  const double sin_w = std::sin(o.wall_normal_deg * kDeg);
  std::vector<std::pair<double, double>> az;  // (azimuth mod 90 in [0, 90) degrees, weight)
  double wall = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s.weight[i] <= 0) continue;
    const Eigen::Vector3d n = level * s.normal[i];
    if (std::fabs(n.z()) > sin_w) continue;
    double a = std::atan2(n.y(), n.x()) / kDeg;
    a = std::fmod(std::fmod(a, 90.0) + 90.0, 90.0);
    az.push_back({a, s.weight[i]});
    wall += s.weight[i];
  }
  if (wall <= 0 || wall < o.min_wall_fraction * s.total) return false;
  const int nb = 360;  // 0.25 degrees.
  std::vector<double> hist(nb, 0.0);
  for (const auto& [a, w] : az) hist[std::min(nb - 1, int(a / 0.25))] += w;
  int best_b = 0;
  double best = -1;
  for (int b = 0; b < nb; ++b) {
    double v = 0;
    for (int d = -4; d <= 4; ++d) v += hist[(b + d + nb) % nb];
    if (v > best) best = v, best_b = b;
  }
  double yaw = (best_b + 0.5) * 0.25;
  // Difference of two angles modulo 90, in (-45, 45].
  auto diff90 = [](double a, double b) {
    double d = std::fmod(a - b, 90.0);
    if (d > 45) d -= 90;
    if (d <= -45) d += 90;
    return d;
  };
  for (int it = 0; it < 3; ++it) {
    double c = 0, sn = 0;
    for (const auto& [a, w] : az)
      if (std::fabs(diff90(a, yaw)) <= 3.0) c += w * std::cos(4 * a * kDeg), sn += w * std::sin(4 * a * kDeg);
    if (c == 0 && sn == 0) break;
    yaw = std::atan2(sn, c) / (4 * kDeg);
  }
  double near = 0;
  for (const auto& [a, w] : az)
    if (std::fabs(diff90(a, yaw)) <= 5.0) near += w;
  if (near < o.min_yaw_concentration * wall) return false;
  yaw = diff90(yaw, 0.0);
  *yaw_deg = yaw;
  return true;
}

// The walls' phase within a grid of period `period` along the levelled, turned frame's x and y: for samples whose
// normal lies within `wall_normal_deg` of +-x (resp. +-y), the weighted circular mean of x (resp. y) modulo the
// period. `shift` is the position of that mean in [-period / 2, period / 2); `concentration` its resultant
// length (1: every wall at one phase; near 0: no preferred phase).
void WallPhase(const Samples& s, const Eigen::Matrix3d& rotation, double period, double wall_normal_deg,
               Eigen::Vector2d* shift, Eigen::Vector2d* concentration) {
  const double cos_w = std::cos(wall_normal_deg * kDeg);
  double c[2] = {0, 0}, sn[2] = {0, 0}, total[2] = {0, 0};
  for (size_t i = 0; i < s.size(); ++i) {
    if (s.weight[i] <= 0) continue;
    const Eigen::Vector3d n = rotation * s.normal[i];
    for (int axis = 0; axis < 2; ++axis) {
      if (std::fabs(n[axis]) < cos_w) continue;
      const double a = 2 * M_PI * (rotation.row(axis) * s.position[i])(0) / period;
      c[axis] += s.weight[i] * std::cos(a);
      sn[axis] += s.weight[i] * std::sin(a);
      total[axis] += s.weight[i];
    }
  }
  for (int axis = 0; axis < 2; ++axis) {
    (*shift)[axis] = 0;
    (*concentration)[axis] = 0;
    if (!(total[axis] > 0)) continue;
    (*concentration)[axis] = std::hypot(c[axis], sn[axis]) / total[axis];
    double d = std::atan2(sn[axis], c[axis]) / (2 * M_PI) * period;  // (-period / 2, period / 2]
    if (d >= 0.5 * period) d -= period;
    (*shift)[axis] = d;
  }
}

std::string Fixed(double v, int digits) {
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(digits);
  os << v;
  return os.str();
}

}  // namespace

bool SceneFrameOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    *error = "scene frame: " + what;
    return false;
  };
  if (!(max_level_deg > 0 && max_level_deg <= 80)) return fail("max_level_deg must be in (0, 80]");
  if (!(warn_tilt_deg >= 0)) return fail("warn_tilt_deg must be >= 0");
  if (!(plane_normal_deg > 0 && plane_normal_deg <= 20)) return fail("plane_normal_deg must be in (0, 20]");
  if (!(min_plane_fraction > 0 && min_plane_fraction < 1)) return fail("min_plane_fraction must be in (0, 1)");
  if (!(horizontal_normal_deg > 0 && horizontal_normal_deg < 90)) return fail("horizontal_normal_deg must be in (0, 90)");
  if (!(wall_normal_deg > 0 && wall_normal_deg < 45)) return fail("wall_normal_deg must be in (0, 45)");
  if (!(min_wall_fraction >= 0 && min_wall_fraction <= 1)) return fail("min_wall_fraction must be in [0, 1]");
  if (!(min_yaw_concentration >= 0 && min_yaw_concentration <= 1)) return fail("min_yaw_concentration must be in [0, 1]");
  if (!(bin_m > 0)) return fail("bin_m must be > 0");
  if (cloud_normal_neighbors < 3) return fail("cloud_normal_neighbors must be >= 3");
  if (max_cloud_points < 100) return fail("max_cloud_points must be >= 100");
  if (!(min_phase_concentration >= 0 && min_phase_concentration <= 1)) return fail("min_phase_concentration must be in [0, 1]");
  if (!(snap_shift_m >= 0)) return fail("snap_shift_m must be >= 0");
  return true;
}

SceneFrame EstimateSceneFrame(const Scene& scene, const SceneFrameOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  SceneFrame f;
  const Samples s = scene.is_mesh() ? MeshSamples(scene.mesh) : CloudSamples(scene.cloud, o);
  const std::string name = scene.source_path.empty() ? std::string("scene") : scene.source_path;
  if (s.total <= 0) {
    f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return f;
  }

  // (a) Up: the dominant horizontal plane family near +Z, its side from the furniture / winding.
  Eigen::Vector3d axis;
  double plane_weight = 0;
  const bool any = DominantAxisNearZ(s, (o.max_level_deg + 5.0) * kDeg, o.plane_normal_deg * kDeg, &axis, &plane_weight);
  Eigen::Matrix3d level = Eigen::Matrix3d::Identity();
  if (!any || plane_weight < o.min_plane_fraction * s.total) {
    f.warnings.push_back(name + ": no dominant horizontal plane within " + Fixed(o.max_level_deg, 0) +
                         " degrees of +Z (floor / ceiling); kept the input up axis. If the file is not +Z up, pass --up "
                         "(e.g. --up y, or --up=-y for a camera's frame with y down) or re-export it +Z up");
  } else {
    f.up_found = true;
    f.upside_down = LooksUpsideDown(s, axis, o.horizontal_normal_deg * kDeg);
    f.up = f.upside_down ? Eigen::Vector3d(-axis) : axis;
    f.tilt_deg = std::acos(std::clamp(f.up.z(), -1.0, 1.0)) / kDeg;
    if (f.upside_down) {
      f.warnings.push_back(name + ": the scan looks upside down (the floor lies above the furniture; estimated up = " +
                           Fixed(f.up.x(), 3) + " " + Fixed(f.up.y(), 3) + " " + Fixed(f.up.z(), 3) +
                           "); kept as loaded. Check --up, or flip the file so that +Z is up");
    } else if (f.tilt_deg > o.max_level_deg) {
      f.warnings.push_back(name + ": the floor is tilted by " + Fixed(f.tilt_deg, 1) + " degrees from +Z (more than " +
                           Fixed(o.max_level_deg, 0) + "); kept the input up axis. Check --up (e.g. --up y, or --up=-y for a camera's frame)");
    } else if (f.tilt_deg >= o.snap_tilt_deg) {
      level = Eigen::Quaterniond::FromTwoVectors(f.up, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      f.levelled = true;
      if (f.tilt_deg > o.warn_tilt_deg)
        f.warnings.push_back(name + ": the scan is tilted by " + Fixed(f.tilt_deg, 1) +
                             " degrees from +Z (estimated up = " + Fixed(f.up.x(), 3) + " " + Fixed(f.up.y(), 3) + " " +
                             Fixed(f.up.z(), 3) + "); levelled. If the file uses another up axis, pass --up");
    }
  }

  // (b) Floor after levelling: the voxeliser's rule on the levelled horizontal samples.
  const double cos_h = std::cos(o.horizontal_normal_deg * kDeg);
  std::vector<std::pair<double, double>> up, down;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s.weight[i] <= 0) continue;
    const double nz = (level.row(2) * s.normal[i])(0), z = (level.row(2) * s.position[i])(0);
    if (!s.oriented) {
      if (std::fabs(nz) >= cos_h) up.push_back({z, s.weight[i]});
    } else {
      if (nz >= cos_h) up.push_back({z, s.weight[i]});
      if (nz <= -cos_h) down.push_back({z, s.weight[i]});
    }
  }
  if (!s.oriented || up.empty() || down.empty()) {  // Unoriented or inconsistent winding: as the voxeliser.
    up.insert(up.end(), down.begin(), down.end());
    down = up;
  }
  const FloorCeiling fc = DetectFloorCeiling(up, down, o.bin_m, o.min_floor_to_ceiling_m);
  if (fc.floor_found) {
    // The rule's height averages over +-1 bin (rugs, skirting, low tops pull it up by a millimetre or so);
    // the floor plane itself is the mean of the horizontal surfaces within 1 cm of it. A floor off by a
    // millimetre below z = 0 would fall into the voxel layer below.
    double z = fc.floor_z;
    for (int it = 0; it < 2; ++it) {
      double sw = 0, sz = 0;
      for (const auto& [h, w] : up)
        if (std::fabs(h - z) <= 0.01) sw += w, sz += w * h;
      if (sw > 0) z = sz / sw;
    }
    f.floor_found = true;
    f.floor_measured_z = z;
    f.floor_z = std::fabs(z) < o.snap_floor_m ? 0.0 : z;
  }

  // (c) Yaw of the walls in the levelled frame.
  double yaw = 0;
  if (WallYaw(s, level, o, &yaw)) {
    f.yaw_found = true;
    f.yaw_measured_deg = yaw;
    f.yaw_deg = std::fabs(yaw) < o.snap_yaw_deg ? 0.0 : yaw;
  }

  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  if (f.levelled) t.linear() = level;
  if (f.yaw_deg != 0) t.prerotate(Eigen::AngleAxisd(-f.yaw_deg * kDeg, Eigen::Vector3d::UnitZ()));

  // (d) The walls' phase within the voxel grid, in the levelled, turned frame.
  if (o.wall_phase && f.yaw_found && (!o.phase_only_when_turned || f.levelled || f.yaw_deg != 0)) {
    Eigen::Vector2d shift;
    WallPhase(s, t.linear(), o.bin_m, o.wall_normal_deg, &shift, &f.phase_concentration);
    for (int axis = 0; axis < 2; ++axis)
      if (f.phase_concentration[axis] >= o.min_phase_concentration && std::fabs(shift[axis]) >= o.snap_shift_m)
        f.shift[axis] = shift[axis];
  }
  if (f.floor_z != 0 || f.shift.x() != 0 || f.shift.y() != 0)
    t.pretranslate(Eigen::Vector3d(-f.shift.x(), -f.shift.y(), -f.floor_z));
  f.canonical_from_input = t;
  f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return f;
}

void TransformScene(const Eigen::Isometry3d& transform, Scene* scene) {
  const Eigen::Matrix3d r = transform.linear();
  auto points = [&](std::vector<Eigen::Vector3f>* v) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, v->size(), 8192), [&](const tbb::blocked_range<size_t>& b) {
      for (size_t i = b.begin(); i != b.end(); ++i) (*v)[i] = (transform * (*v)[i].cast<double>()).cast<float>();
    });
  };
  auto normals = [&](std::vector<Eigen::Vector3f>* v) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, v->size(), 8192), [&](const tbb::blocked_range<size_t>& b) {
      for (size_t i = b.begin(); i != b.end(); ++i) (*v)[i] = (r * (*v)[i].cast<double>()).cast<float>();
    });
  };
  points(&scene->mesh.vertices);
  points(&scene->cloud.points);
  normals(&scene->cloud.normals);
}

}  // namespace semvox
