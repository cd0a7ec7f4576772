#include "core/mesh_ply.h"

#include "core/ply.h"

namespace semvox {
namespace {

void AddPositionsAndColors(PlyWriter* w, const std::vector<Eigen::Vector3f>& pts, const std::vector<Rgb8>& colors) {
  const size_t n = pts.size();
  std::vector<double> x(n), y(n), z(n);
  for (size_t i = 0; i < n; ++i) x[i] = pts[i].x(), y[i] = pts[i].y(), z[i] = pts[i].z();
  w->AddProperty("x", PlyType::kFloat32, std::move(x));
  w->AddProperty("y", PlyType::kFloat32, std::move(y));
  w->AddProperty("z", PlyType::kFloat32, std::move(z));
  if (colors.size() == n && n > 0) {
    std::vector<double> r(n), g(n), b(n);
    for (size_t i = 0; i < n; ++i) r[i] = colors[i].r, g[i] = colors[i].g, b[i] = colors[i].b;
    w->AddProperty("red", PlyType::kUInt8, std::move(r));
    w->AddProperty("green", PlyType::kUInt8, std::move(g));
    w->AddProperty("blue", PlyType::kUInt8, std::move(b));
  }
}

}  // namespace

Status WriteMeshPly(const std::string& path, const Mesh& mesh, const std::string& comment) {
  PlyWriter w;
  if (!comment.empty()) w.AddComment(comment);
  w.AddElement("vertex", mesh.vertices.size());
  AddPositionsAndColors(&w, mesh.vertices, mesh.vertex_colors);
  w.AddElement("face", mesh.faces.size());
  std::vector<double> idx(mesh.faces.size() * 3);
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) idx[f * 3 + k] = mesh.faces[f][k];
  w.AddListProperty("vertex_indices", PlyType::kUInt8, PlyType::kInt32, 3, std::move(idx));
  for (const auto& [name, values] : mesh.face_attributes) {
    if (values.size() != mesh.faces.size()) continue;
    w.AddProperty(name, PlyType::kInt32, std::vector<double>(values.begin(), values.end()));
  }
  return w.Write(path);
}

Status WriteCloudPly(const std::string& path, const PointCloud& cloud, const std::string& comment) {
  PlyWriter w;
  if (!comment.empty()) w.AddComment(comment);
  const size_t n = cloud.points.size();
  w.AddElement("vertex", n);
  AddPositionsAndColors(&w, cloud.points, cloud.colors);
  if (cloud.normals.size() == n && n > 0) {
    std::vector<double> a(n), b(n), c(n);
    for (size_t i = 0; i < n; ++i) a[i] = cloud.normals[i].x(), b[i] = cloud.normals[i].y(), c[i] = cloud.normals[i].z();
    w.AddProperty("nx", PlyType::kFloat32, std::move(a));
    w.AddProperty("ny", PlyType::kFloat32, std::move(b));
    w.AddProperty("nz", PlyType::kFloat32, std::move(c));
  }
  for (const auto& [name, values] : cloud.point_attributes)
    if (values.size() == n) w.AddProperty(name, PlyType::kInt32, std::vector<double>(values.begin(), values.end()));
  return w.Write(path);
}

}  // namespace semvox
