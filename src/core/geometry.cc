#include "core/geometry.h"

#include <algorithm>
#include <cmath>

namespace semvox {

bool Mesh::has_texture() const {
  for (const Material& m : materials)
    if (!m.texture.empty()) return true;
  return false;
}

Rgb8 Mesh::ColorAt(int face, float u, float v) const {
  const Eigen::Vector3i& f = faces[face];
  const float w = 1.0f - u - v;
  if (!face_material.empty() && !uvs.empty()) {
    const Material& m = materials[face_material[face]];
    if (!m.texture.empty()) {
      Eigen::Vector2f uv = w * uvs[f[0]] + u * uvs[f[1]] + v * uvs[f[2]];
      float tu = uv.x() - std::floor(uv.x());
      float tv = uv.y() - std::floor(uv.y());
      int x = std::clamp(int(tu * m.texture.width), 0, m.texture.width - 1);
      int y = std::clamp(int((1.0f - tv) * m.texture.height), 0, m.texture.height - 1);
      return Rgb8{m.texture.at(x, y, 0), m.texture.at(x, y, 1), m.texture.at(x, y, 2)};
    }
  }
  if (!vertex_colors.empty()) {
    const Rgb8 &a = vertex_colors[f[0]], &b = vertex_colors[f[1]], &c = vertex_colors[f[2]];
    auto mix = [&](uint8_t ca, uint8_t cb, uint8_t cc) {
      return uint8_t(std::clamp(std::lround(w * ca + u * cb + v * cc), 0L, 255L));
    };
    return Rgb8{mix(a.r, b.r, c.r), mix(a.g, b.g, c.g), mix(a.b, b.b, c.b)};
  }
  if (!face_material.empty()) return materials[face_material[face]].diffuse;
  return Rgb8{200, 200, 200};
}

Aabb Scene::Bounds() const {
  Aabb box;
  if (is_mesh()) {
    for (const auto& v : mesh.vertices) box.Extend(v);
  } else {
    for (const auto& p : cloud.points) box.Extend(p);
  }
  return box;
}

}  // namespace semvox
