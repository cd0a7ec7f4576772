// Meshes and clouds as binary PLY, with per-face / per-point integer attributes (label, instance, room).
#pragma once

#include <string>

#include "core/geometry.h"
#include "core/status.h"

namespace semvox {

// Vertices (x, y, z float; red, green, blue uchar when present) and faces (vertex_indices plus every
// face attribute as int). Written atomically.
Status WriteMeshPly(const std::string& path, const Mesh& mesh, const std::string& comment = "");
// Points (x, y, z; colours and normals when present; every point attribute as int). Written atomically.
Status WriteCloudPly(const std::string& path, const PointCloud& cloud, const std::string& comment = "");

}  // namespace semvox
