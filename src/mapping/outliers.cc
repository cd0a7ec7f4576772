#include "mapping/outliers.h"

#include <algorithm>

namespace semvox {

OutlierReport TrimOutliers(Scene* scene, const OutlierOptions& options) {
  OutlierReport report;
  std::vector<Eigen::Vector3f>& pts = scene->is_mesh() ? scene->mesh.vertices : scene->cloud.points;
  const size_t n = pts.size();
  if (n < 100) {  // Too few samples for quantiles; nothing is called an outlier.
    for (const auto& p : pts) report.kept_box.Extend(p);
    return report;
  }
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<float> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = pts[i][axis];
    const size_t lo_i = size_t(options.quantile * double(n - 1)), hi_i = size_t((1.0 - options.quantile) * double(n - 1));
    std::nth_element(v.begin(), v.begin() + lo_i, v.end());
    const float lo = v[lo_i];
    std::nth_element(v.begin(), v.begin() + hi_i, v.end());
    const float hi = v[hi_i];
    const float margin = float(std::max(options.min_margin_m, options.margin_factor * double(hi - lo)));
    report.kept_box.min[axis] = lo - margin;
    report.kept_box.max[axis] = hi + margin;
  }
  auto inside = [&](const Eigen::Vector3f& p) {
    return (p.array() >= report.kept_box.min.array()).all() && (p.array() <= report.kept_box.max.array()).all();
  };
  if (scene->is_mesh()) {
    Mesh& m = scene->mesh;
    std::vector<char> keep(m.faces.size(), 1);
    for (size_t i = 0; i < n; ++i) report.removed_vertices += !inside(pts[i]);
    if (report.removed_vertices == 0) return report;
    for (size_t f = 0; f < m.faces.size(); ++f)
      for (int k = 0; k < 3; ++k) keep[f] &= char(inside(m.vertices[m.faces[f][k]]));
    auto compact = [&](auto& v) {
      if (v.size() != keep.size()) return;
      size_t j = 0;
      for (size_t f = 0; f < keep.size(); ++f)
        if (keep[f]) v[j++] = v[f];
      v.resize(j);
    };
    const size_t before = m.faces.size();
    compact(m.face_material);
    for (auto& [name, values] : m.face_attributes) compact(values);
    compact(m.faces);
    report.removed_faces = before - m.faces.size();
    // Move stray vertices onto the first kept vertex so that bounds reflect the kept geometry.
    const Eigen::Vector3f anchor = m.faces.empty() ? Eigen::Vector3f::Zero() : m.vertices[m.faces[0][0]];
    for (auto& p : m.vertices)
      if (!inside(p)) p = anchor;
  } else {
    PointCloud& c = scene->cloud;
    std::vector<char> keep(n);
    for (size_t i = 0; i < n; ++i) keep[i] = inside(pts[i]);
    auto compact = [&](auto& v) {
      if (v.size() != n) return;
      size_t j = 0;
      for (size_t i = 0; i < n; ++i)
        if (keep[i]) v[j++] = v[i];
      v.resize(j);
    };
    compact(c.colors);
    compact(c.normals);
    for (auto& [name, values] : c.point_attributes) compact(values);
    compact(c.points);
    report.removed_vertices = n - c.points.size();
  }
  return report;
}

}  // namespace semvox
