#include "perception/observations.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace semvox {

bool ObservationOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(min_depth_fraction > 0 && min_depth_fraction <= 1))
    return fail("min_depth_fraction = " + std::to_string(min_depth_fraction) +
                ". Violated constraint: 0 < min_depth_fraction <= 1");
  if (!(edge_gradient_min >= 0))
    return fail("edge_gradient_min = " + std::to_string(edge_gradient_min) + ". Violated constraint: edge_gradient_min >= 0");
  if (!(vanishing_angle_max_deg > 0 && vanishing_angle_max_deg < 90))
    return fail("vanishing_angle_max_deg = " + std::to_string(vanishing_angle_max_deg) +
                ". Violated constraint: 0 < vanishing_angle_max_deg < 90");
  return true;
}

double HistogramEntropy(const std::array<int, 4>& counts) {
  double total = 0;
  for (int c : counts) total += c;
  if (total <= 0) return 0.0;
  double h = 0;
  for (int c : counts)
    if (c > 0) h -= (c / total) * std::log(c / total);
  return h;
}

namespace {

// Per-superpixel running sums.
struct Accumulator {
  int pixels = 0;
  double sum_x = 0, sum_y = 0;
  Eigen::Vector3d lab_sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d lab_sq = Eigen::Vector3d::Zero();
  int hits = 0;
  double depth_sum = 0;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // First hit point: sums are taken relative to it.
  Eigen::Vector3d p_sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d pp_sum = Eigen::Matrix3d::Zero();
  std::array<int, 4> vanishing_hist{};  // Three vanishing points, then "none".
};

}  // namespace

Image<int8_t> VanishingMembership(const RenderedView& view, const ImageF32& lab, const ObservationOptions& options) {
  const int w = lab.width, h = lab.height;
  Image<int8_t> out(w, h, 1, int8_t(-1));
  // Vanishing points of the world axes in homogeneous pixel coordinates: v_k = K * R_cam_from_world * e_k.
  const Eigen::Matrix3d cam_from_world = view.world_from_camera.rotation().transpose();
  Eigen::Matrix3d K;
  K << view.camera.fx, 0, view.camera.cx, 0, view.camera.fy, view.camera.cy, 0, 0, 1;
  std::array<Eigen::Vector3d, 3> vp;
  for (int k = 0; k < 3; ++k) vp[k] = K * cam_from_world.col(k);
  const double sin_max = std::sin(options.vanishing_angle_max_deg * M_PI / 180.0);
  auto L = [&](int xx, int yy) { return double(lab.at(xx, yy, 0)); };
  for (int y = 1; y + 1 < h; ++y) {
    for (int x = 1; x + 1 < w; ++x) {
      // Sobel on L, normalised by 1/8 so the magnitude is in L units per pixel.
      const double gx = (L(x + 1, y - 1) + 2 * L(x + 1, y) + L(x + 1, y + 1) - L(x - 1, y - 1) - 2 * L(x - 1, y) -
                         L(x - 1, y + 1)) / 8.0;
      const double gy = (L(x - 1, y + 1) + 2 * L(x, y + 1) + L(x + 1, y + 1) - L(x - 1, y - 1) - 2 * L(x, y - 1) -
                         L(x + 1, y - 1)) / 8.0;
      const double g = std::hypot(gx, gy);
      if (g < options.edge_gradient_min || g == 0) continue;
      // Edge direction is perpendicular to the gradient; the direction towards vanishing point k from the
      // pixel p is v_k.xy - p * v_k.z (also right for a vanishing point at infinity, v_k.z = 0).
      const Eigen::Vector2d edge(-gy / g, gx / g);
      const Eigen::Vector2d p(x + 0.5, y + 0.5);
      int best = 3;
      double best_sin = sin_max;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d dir = vp[k].head<2>() - p * vp[k].z();
        const double len = dir.norm();
        if (len < 1e-9) continue;  // The pixel is at the vanishing point: no direction.
        const double s_angle = std::abs(edge.x() * dir.y() - edge.y() * dir.x()) / len;
        if (s_angle <= best_sin) {
          best_sin = s_angle;
          best = k;
        }
      }
      out.at(x, y) = int8_t(best);
    }
  }
  return out;
}

Result<ViewObservations> ComputeObservations(const RenderedView& view, const Superpixels& superpixels,
                                             const ObservationOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("observations: " + error);
  const int w = view.rgb.width, h = view.rgb.height;
  if (w <= 0 || h <= 0 || view.rgb.channels != 3 || superpixels.label.width != w ||
      superpixels.label.height != h || view.depth.width != w || view.depth.height != h ||
      view.normal.width != w || view.normal.height != h || superpixels.count <= 0)
    return Status::InvalidInput("observations: the view's rgb, depth, normal and superpixel labels must share one "
                                "non-empty size (rgb " + std::to_string(w) + "x" + std::to_string(h) +
                                ", labels " + std::to_string(superpixels.label.width) + "x" +
                                std::to_string(superpixels.label.height) + ")");
  const int n = superpixels.count;
  const ImageF32 lab = RgbToLab(view.rgb);
  std::vector<Accumulator> acc(static_cast<size_t>(n));

  const Image<int8_t> membership = VanishingMembership(view, lab, options);

  std::vector<std::pair<int, int>> adjacency;
  const auto& label = superpixels.label;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int s = label.at(x, y);
      if (s < 0 || s >= n) return Status::InvalidInput("observations: superpixel label out of range at pixel (" +
                                                       std::to_string(x) + ", " + std::to_string(y) + ")");
      Accumulator& a = acc[size_t(s)];
      ++a.pixels;
      a.sum_x += x + 0.5;
      a.sum_y += y + 0.5;
      const Eigen::Vector3d c(lab.at(x, y, 0), lab.at(x, y, 1), lab.at(x, y, 2));
      a.lab_sum += c;
      a.lab_sq += c.cwiseProduct(c);
      const float d = view.depth.at(x, y);
      if (d > 0 && std::isfinite(d)) {
        const Eigen::Vector3d p = view.world_from_camera * (view.camera.PixelRay(x, y) * double(d));
        if (a.hits == 0) a.origin = p;
        const Eigen::Vector3d q = p - a.origin;
        ++a.hits;
        a.depth_sum += d;
        a.p_sum += q;
        a.pp_sum += q * q.transpose();
      }
      // Adjacency and boundary pixels (4-connected: right and down neighbours suffice for pairs).
      bool boundary = false;
      if (x + 1 < w && label.at(x + 1, y) != s) {
        adjacency.emplace_back(std::min(s, label.at(x + 1, y)), std::max(s, label.at(x + 1, y)));
        boundary = true;
      }
      if (y + 1 < h && label.at(x, y + 1) != s) {
        adjacency.emplace_back(std::min(s, label.at(x, y + 1)), std::max(s, label.at(x, y + 1)));
        boundary = true;
      }
      if (!boundary) boundary = (x > 0 && label.at(x - 1, y) != s) || (y > 0 && label.at(x, y - 1) != s);
      if (!boundary) continue;
      const int8_t m = membership.at(x, y);
      if (m >= 0) ++a.vanishing_hist[size_t(m)];
    }
  }
  std::sort(adjacency.begin(), adjacency.end());
  adjacency.erase(std::unique(adjacency.begin(), adjacency.end()), adjacency.end());

  ViewObservations out;
  out.image_adjacency = adjacency;
  out.superpixels.resize(size_t(n));
  const Eigen::Vector3d camera_position = view.world_from_camera.translation();
  for (int s = 0; s < n; ++s) {
    const Accumulator& a = acc[size_t(s)];
    SuperpixelObservation& o = out.superpixels[size_t(s)];
    o.pixel_count = a.pixels;
    o.hit_count = a.hits;
    if (a.pixels == 0) continue;
    const Eigen::Vector3d mean = a.lab_sum / a.pixels;
    const Eigen::Vector3d var = (a.lab_sq / a.pixels - mean.cwiseProduct(mean)).cwiseMax(0.0);
    o.lab_mean = mean.cast<float>();
    for (int c = 0; c < 3; ++c) {
      o.z[size_t(kObsLabMeanL + c)] = float(mean[c]);
      o.z[size_t(kObsLabStdL + c)] = float(std::sqrt(var[c]));
    }
    o.centroid_px = {a.sum_x / a.pixels, a.sum_y / a.pixels};
    o.z[kObsVerticalPosition] = float(o.centroid_px.y() / h);
    o.z[kObsVanishingEntropy] = float(HistogramEntropy(a.vanishing_hist));
    o.has_depth = a.hits > 0 && a.hits >= options.min_depth_fraction * a.pixels;
    if (!o.has_depth) continue;  // 3D features keep the table's default, 0.
    const Eigen::Vector3d q_mean = a.p_sum / a.hits;
    o.centroid_world = a.origin + q_mean;
    o.z[kObsHeight] = float(o.centroid_world.z());
    o.z[kObsDepth] = float(a.depth_sum / a.hits);
    if (a.hits >= 3) {
      const Eigen::Matrix3d cov = a.pp_sum / a.hits - q_mean * q_mean.transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);  // Ascending eigenvalues.
      const Eigen::Vector3d l = eig.eigenvalues().cwiseMax(0.0);
      const double sum = l.sum();
      o.z[kObsPlanarity] = sum > 0 ? float(3.0 * l[0] / sum) : 0.0f;
      Eigen::Vector3d normal = eig.eigenvectors().col(0).normalized();
      if (normal.dot(camera_position - o.centroid_world) < 0) normal = -normal;
      o.normal_world = normal;
      o.z[kObsOrientation] = float(normal.head<2>().norm());
    }
  }
  // Neighbourhood features: in-front-of depth differences and neighbourhood planarity.
  std::vector<std::vector<int>> neighbours(static_cast<size_t>(n));
  for (const auto& [i, j] : adjacency) {
    neighbours[size_t(i)].push_back(j);
    neighbours[size_t(j)].push_back(i);
  }
  for (int s = 0; s < n; ++s) {
    SuperpixelObservation& o = out.superpixels[size_t(s)];
    if (!o.has_depth) continue;
    const double ds = o.z[kObsDepth];
    double sum_d = 0, sum_diff = 0, sum_diff_sq = 0, sum_dot = 0;
    int count = 0, normal_count = 0;
    for (int j : neighbours[size_t(s)]) {
      const SuperpixelObservation& q = out.superpixels[size_t(j)];
      if (!q.has_depth) continue;
      const double diff = std::abs(ds - q.z[kObsDepth]);
      sum_d += q.z[kObsDepth];
      sum_diff += diff;
      sum_diff_sq += diff * diff;
      ++count;
      if (o.normal_world.squaredNorm() > 0 && q.normal_world.squaredNorm() > 0) {
        sum_dot += std::abs(o.normal_world.dot(q.normal_world));
        ++normal_count;
      }
    }
    if (count > 0 && ds < sum_d / count) {  // In front of its neighbourhood.
      const double m = sum_diff / count;
      o.z[kObsInFrontMean] = float(m);
      o.z[kObsInFrontStd] = float(std::sqrt(std::max(0.0, sum_diff_sq / count - m * m)));
    }
    if (normal_count > 0) o.z[kObsNeighbourPlanarity] = float(1.0 - sum_dot / normal_count);
  }
  return out;
}

}  // namespace semvox
