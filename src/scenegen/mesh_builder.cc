#include "scenegen/mesh_builder.h"

#include <cmath>

namespace semvox {

MeshBuilder::MeshBuilder() {
  mesh_.face_attributes["label"];
  mesh_.face_attributes["instance"];
  mesh_.face_attributes["room"];
}

void MeshBuilder::AddTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, Rgb8 color,
                              const FaceTags& tags) {
  const int base = int(mesh_.vertices.size());
  for (const Eigen::Vector3d* p : {&a, &b, &c}) {
    mesh_.vertices.push_back(p->cast<float>());
    mesh_.vertex_colors.push_back(color);
  }
  mesh_.faces.emplace_back(base, base + 1, base + 2);
  mesh_.face_attributes["label"].push_back(tags.label);
  mesh_.face_attributes["instance"].push_back(tags.instance);
  mesh_.face_attributes["room"].push_back(tags.room);
}

void MeshBuilder::AddQuad(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                          const Eigen::Vector3d& d, Rgb8 color, const FaceTags& tags) {
  const int base = int(mesh_.vertices.size());
  for (const Eigen::Vector3d* p : {&a, &b, &c, &d}) {
    mesh_.vertices.push_back(p->cast<float>());
    mesh_.vertex_colors.push_back(color);
  }
  mesh_.faces.emplace_back(base, base + 1, base + 2);
  mesh_.faces.emplace_back(base, base + 2, base + 3);
  for (int k = 0; k < 2; ++k) {
    mesh_.face_attributes["label"].push_back(tags.label);
    mesh_.face_attributes["instance"].push_back(tags.instance);
    mesh_.face_attributes["room"].push_back(tags.room);
  }
}

void MeshBuilder::AddBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Rgb8 color, const FaceTags& tags,
                         double yaw_rad, bool skip_bottom) {
  const Eigen::Vector3d c = 0.5 * (lo + hi);
  const double cs = std::cos(yaw_rad), sn = std::sin(yaw_rad);
  auto P = [&](double x, double y, double z) {
    const double dx = x - c.x(), dy = y - c.y();
    return Eigen::Vector3d(c.x() + cs * dx - sn * dy, c.y() + sn * dx + cs * dy, z);
  };
  const double x0 = lo.x(), y0 = lo.y(), z0 = lo.z(), x1 = hi.x(), y1 = hi.y(), z1 = hi.z();
  AddQuad(P(x0, y0, z1), P(x1, y0, z1), P(x1, y1, z1), P(x0, y1, z1), color, tags);  // top (+z)
  if (!skip_bottom) AddQuad(P(x0, y0, z0), P(x0, y1, z0), P(x1, y1, z0), P(x1, y0, z0), color, tags);  // bottom
  AddQuad(P(x0, y0, z0), P(x1, y0, z0), P(x1, y0, z1), P(x0, y0, z1), color, tags);  // -y
  AddQuad(P(x1, y1, z0), P(x0, y1, z0), P(x0, y1, z1), P(x1, y1, z1), color, tags);  // +y
  AddQuad(P(x0, y1, z0), P(x0, y0, z0), P(x0, y0, z1), P(x0, y1, z1), color, tags);  // -x
  AddQuad(P(x1, y0, z0), P(x1, y1, z0), P(x1, y1, z1), P(x1, y0, z1), color, tags);  // +x
}

}  // namespace semvox
