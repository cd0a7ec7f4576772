// Scene geometry in core types: a triangle mesh or a point cloud, in metres, +Z up, in the input's frame.
//
// Loaders (src/io) fill these; mapping, render and the generator read them. Per-element integer
// attributes ("label", "instance", "room") travel in parallel arrays keyed by name so that any number of
// them can be carried without custom point types.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "core/image.h"

namespace semvox {

struct Rgb8 {
  uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb8& o) const { return r == o.r && g == o.g && b == o.b; }
};

struct Material {
  std::string name;
  Rgb8 diffuse{200, 200, 200};  // Used where there is no texture.
  ImageRgb8 texture;            // Empty when the material has no (loadable) diffuse texture.
  std::string texture_path;     // As referenced by the file, for reports.
};

struct Mesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3i> faces;       // Triangles, indices into vertices.
  std::vector<Rgb8> vertex_colors;          // Empty or one per vertex.
  std::vector<Eigen::Vector2f> uvs;         // Empty or one per vertex (texture coordinates, v up).
  std::vector<int> face_material;           // Empty or one per face, index into materials.
  std::vector<Material> materials;
  std::map<std::string, std::vector<int32_t>> face_attributes;  // e.g. "label", "instance", "room".

  bool has_vertex_colors() const { return !vertex_colors.empty(); }
  bool has_texture() const;
  // Colour of a surface point given by face and barycentric coordinates (u, v): texture, then vertex
  // colour, then material colour, then grey.
  Rgb8 ColorAt(int face, float u, float v) const;
};

struct PointCloud {
  std::vector<Eigen::Vector3f> points;
  std::vector<Rgb8> colors;                 // Empty or one per point.
  std::vector<Eigen::Vector3f> normals;     // Empty or one per point (unit length).
  std::map<std::string, std::vector<int32_t>> point_attributes;  // e.g. "label".

  bool has_colors() const { return !colors.empty(); }
};

struct Aabb {
  Eigen::Vector3f min{Eigen::Vector3f::Constant(std::numeric_limits<float>::max())};
  Eigen::Vector3f max{Eigen::Vector3f::Constant(-std::numeric_limits<float>::max())};
  void Extend(const Eigen::Vector3f& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  bool valid() const { return (min.array() <= max.array()).all(); }
  Eigen::Vector3f extent() const { return max - min; }
};

// Whether a rigid transform is exactly the identity. Coordinate writers take an `input_from_world` transform
// (the canonical frame back to the input's, mapping/scene_frame.h) and leave values untouched under the
// identity, so that outputs of axis-aligned inputs stay byte-identical.
inline bool IsIdentity(const Eigen::Isometry3d& t) { return t.matrix() == Eigen::Matrix4d::Identity(); }

// What was loaded: exactly one of mesh / cloud is non-empty.
struct Scene {
  std::string source_path;
  std::string format;  // "ply", "obj", "gltf", "pcd", "txt", ...
  Mesh mesh;
  PointCloud cloud;
  bool is_mesh() const { return !mesh.faces.empty(); }
  Aabb Bounds() const;
  size_t dropped_non_finite = 0;  // Vertices / points dropped by the loader.
};

}  // namespace semvox
