#include "io/load_scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/file_util.h"
#include "core/log.h"
#include "core/ply.h"
#include "io/image_io.h"

namespace semvox {
namespace {

const char* kMeshExtensions[] = {"obj", "gltf", "glb", "off", "stl", "fbx", "dae", "3ds"};

bool IsOneOf(const std::string& ext, std::initializer_list<const char*> list) {
  for (const char* e : list)
    if (ext == e) return true;
  return false;
}

// Drops vertices with non-finite coordinates and the faces that use them, re-indexing the rest.
size_t DropNonFiniteMesh(Mesh* mesh) {
  const size_t n = mesh->vertices.size();
  std::vector<int> remap(n, -1);
  int next = 0;
  for (size_t i = 0; i < n; ++i)
    if (mesh->vertices[i].allFinite()) remap[i] = next++;
  const size_t dropped = n - size_t(next);
  if (dropped == 0) return 0;
  auto compact = [&](auto& v) {
    if (v.size() != n) return;
    size_t k = 0;
    for (size_t i = 0; i < n; ++i)
      if (remap[i] >= 0) v[k++] = v[i];
    v.resize(k);
  };
  compact(mesh->vertices);
  compact(mesh->vertex_colors);
  compact(mesh->uvs);
  size_t kf = 0;
  const size_t nf = mesh->faces.size();
  std::vector<char> keep(nf, 0);
  for (size_t f = 0; f < nf; ++f) {
    const auto& t = mesh->faces[f];
    if (remap[t[0]] < 0 || remap[t[1]] < 0 || remap[t[2]] < 0) continue;
    keep[f] = 1;
  }
  auto compact_faces = [&](auto& v) {
    if (v.size() != nf) return;
    size_t k = 0;
    for (size_t f = 0; f < nf; ++f)
      if (keep[f]) v[k++] = v[f];
    v.resize(k);
  };
  for (size_t f = 0; f < nf; ++f)
    if (keep[f]) {
      auto& t = mesh->faces[f];
      t = Eigen::Vector3i(remap[t[0]], remap[t[1]], remap[t[2]]);
    }
  compact_faces(mesh->faces);
  compact_faces(mesh->face_material);
  for (auto& [name, values] : mesh->face_attributes) compact_faces(values);
  (void)kf;
  return dropped;
}

size_t DropNonFiniteCloud(PointCloud* cloud) {
  const size_t n = cloud->points.size();
  std::vector<char> keep(n);
  size_t kept = 0;
  for (size_t i = 0; i < n; ++i) kept += (keep[i] = cloud->points[i].allFinite());
  if (kept == n) return 0;
  auto compact = [&](auto& v) {
    if (v.size() != n) return;
    size_t k = 0;
    for (size_t i = 0; i < n; ++i)
      if (keep[i]) v[k++] = v[i];
    v.resize(k);
  };
  compact(cloud->points);
  compact(cloud->colors);
  compact(cloud->normals);
  for (auto& [name, values] : cloud->point_attributes) compact(values);
  return n - kept;
}

// The rotation that takes the file's up axis to +Z (a proper rotation: handedness is kept).
Eigen::Matrix3f UpToZ(UpAxis up) {
  Eigen::Matrix3f r;
  switch (up) {
    case UpAxis::kY: r << 1, 0, 0, 0, 0, -1, 0, 1, 0; break;      // +90 deg about X: +Y -> +Z, +Z -> -Y.
    case UpAxis::kNegY: r << 1, 0, 0, 0, 0, 1, 0, -1, 0; break;   // -90 deg about X: -Y -> +Z, +Z (forward) -> +Y.
    case UpAxis::kX: r << 0, 0, -1, 0, 1, 0, 1, 0, 0; break;      // -90 deg about Y: +X -> +Z.
    case UpAxis::kNegX: r << 0, 0, 1, 0, 1, 0, -1, 0, 0; break;   // +90 deg about Y: -X -> +Z.
    case UpAxis::kNegZ: r << 1, 0, 0, 0, -1, 0, 0, 0, -1; break;  // 180 deg about X.
    default: r.setIdentity();
  }
  return r;
}

void Transform(Scene* scene, UpAxis up, double scale) {
  const Eigen::Matrix3f r = UpToZ(up);
  for (auto& v : scene->mesh.vertices) v = float(scale) * (r * v);
  for (auto& v : scene->cloud.points) v = float(scale) * (r * v);
  if (!r.isIdentity())
    for (auto& n : scene->cloud.normals) n = r * n;
}

}  // namespace

bool ParseUpAxis(const std::string& name, UpAxis* up) {
  if (name == "auto") *up = UpAxis::kAuto;
  else if (name == "z" || name == "+z") *up = UpAxis::kZ;
  else if (name == "y" || name == "+y") *up = UpAxis::kY;
  else if (name == "-y") *up = UpAxis::kNegY;
  else if (name == "x" || name == "+x") *up = UpAxis::kX;
  else if (name == "-x") *up = UpAxis::kNegX;
  else if (name == "-z") *up = UpAxis::kNegZ;
  else return false;
  return true;
}

bool LoadOptions::Check(std::string* error) const {
  if (!CheckOptions(*this, Options(), error)) return false;
  if (min_valid_points < 1) {
    *error = "min_valid_points = " + std::to_string(min_valid_points) + ". Violated constraint: min_valid_points >= 1";
    return false;
  }
  return true;
}

std::string SupportedExtensions() {
  return "meshes: .ply .obj .gltf .glb .off .stl (also .fbx .dae .3ds); clouds: .ply (no faces) .pcd .txt .xyz .pts";
}

Result<Scene> LoadScene(const std::string& path, const LoadOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput(error);
  const std::string ext = LowerExtension(path);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    return Status::InvalidInput(FileError(path, "no such file", "check the path and the working directory"));
  if (std::filesystem::is_directory(path, ec))
    return Status::InvalidInput(FileError(path, "is a directory, expected a mesh or point cloud file",
                                          "pass the file inside it"));
  if (std::filesystem::file_size(path, ec) == 0)
    return Status::InvalidInput(FileError(path, "file is empty", "check that the export finished"));

  Result<Scene> loaded = Status::Internal("unreachable");
  bool mesh_format = false;
  if (ext == "ply") {
    loaded = LoadPlyScene(path);
  } else if (ext == "pcd") {
    loaded = LoadPcdScene(path);
  } else if (IsOneOf(ext, {"txt", "xyz", "pts", "xyzrgb"})) {
    loaded = LoadTextCloud(path);
  } else {
    bool known = false;
    for (const char* e : kMeshExtensions) known |= ext == e;
    if (!known)
      return Status::InvalidInput(FileError(path, "unsupported file extension '." + ext + "'",
                                            "supported: " + SupportedExtensions()));
    mesh_format = true;
    loaded = LoadAssimpScene(path);
  }
  if (!loaded.ok()) return loaded.status();
  Scene scene = std::move(loaded).value();
  scene.source_path = path;
  scene.format = ext;

  if (mesh_format && scene.mesh.faces.empty())
    return Status::InvalidInput(FileError(path, "mesh has no faces",
                                          "for point clouds use .ply without faces, .pcd or .txt/.xyz"));

  const size_t dropped = scene.is_mesh() ? DropNonFiniteMesh(&scene.mesh) : DropNonFiniteCloud(&scene.cloud);
  scene.dropped_non_finite = dropped;
  if (dropped > 0)
    SEMVOX_WARN(path << ": dropped " << dropped << (scene.is_mesh() ? " vertices" : " points")
                     << " with non-finite coordinates (NaN or Inf)");
  if (mesh_format && scene.mesh.faces.empty())
    return Status::InvalidInput(FileError(path, "no faces left after dropping non-finite vertices",
                                          "the mesh has no valid geometry"));

  const size_t valid = scene.is_mesh() ? scene.mesh.vertices.size() : scene.cloud.points.size();
  if (valid < size_t(options.min_valid_points))
    return Status::InvalidInput(FileError(path, "too little valid geometry to build a map (" + std::to_string(valid) +
                                                    " valid " + (scene.is_mesh() ? "vertices" : "points") + ")",
                                          "check the export; NaN points are dropped"));

  const bool gltf = options.up == UpAxis::kAuto && (ext == "gltf" || ext == "glb");
  const UpAxis up = gltf ? UpAxis::kY : options.up;
  if ((up != UpAxis::kAuto && up != UpAxis::kZ) || options.scale != 1.0) Transform(&scene, up, options.scale);
  if (gltf) SEMVOX_INFO(path << ": glTF is +Y up by specification; converted to +Z up");

  // Units check on the robust extent (0.1% .. 99.9% quantiles of a subsample), so that a single stray
  // point does not look like millimetres; mapping trims such strays later.
  const std::vector<Eigen::Vector3f>& pts = scene.is_mesh() ? scene.mesh.vertices : scene.cloud.points;
  const size_t stride = std::max<size_t>(1, pts.size() / 100000);
  float largest = 0;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<float> v;
    for (size_t i = 0; i < pts.size(); i += stride) v.push_back(pts[i][axis]);
    const size_t lo = size_t(0.001 * double(v.size() - 1)), hi = size_t(0.999 * double(v.size() - 1));
    std::nth_element(v.begin(), v.begin() + lo, v.end());
    const float vlo = v[lo];
    std::nth_element(v.begin(), v.begin() + hi, v.end());
    largest = std::max(largest, v[hi] - vlo);
  }
  if (largest > options.millimetre_warning_extent_m)
    SEMVOX_WARN(path << ": the scene is " << largest << " m across, which suggests millimetres or centimetres; "
                     << "pass --scale 0.001 (mm) or --scale 0.01 (cm) if so");
  return scene;
}

Result<Scene> LoadPlyScene(const std::string& path) {
  Result<PlyData> ply_or = ReadPly(path);
  if (!ply_or.ok()) return ply_or.status();
  const PlyData& ply = ply_or.value();
  const PlyElement* vertex = ply.Find("vertex");
  if (!vertex)
    return Status::InvalidInput(FileError(path, "PLY has no 'vertex' element", "export vertices as 'vertex'"));
  const PlyProperty* px = vertex->Find("x");
  const PlyProperty* py = vertex->Find("y");
  const PlyProperty* pz = vertex->Find("z");
  if (!px || !py || !pz || px->is_list || py->is_list || pz->is_list)
    return Status::InvalidInput(FileError(path, "PLY vertex element lacks scalar x, y, z properties",
                                          "export vertex positions as x, y, z"));
  const size_t n = vertex->count;
  std::vector<Eigen::Vector3f> positions(n);
  for (size_t i = 0; i < n; ++i) positions[i] = Eigen::Vector3f(float(px->values[i]), float(py->values[i]), float(pz->values[i]));

  auto find_any = [&](std::initializer_list<const char*> names) -> const PlyProperty* {
    for (const char* nm : names)
      if (const PlyProperty* p = vertex->Find(nm); p && !p->is_list) return p;
    return nullptr;
  };
  std::vector<Rgb8> colors;
  const PlyProperty* pr = find_any({"red", "r", "diffuse_red"});
  const PlyProperty* pg = find_any({"green", "g", "diffuse_green"});
  const PlyProperty* pb = find_any({"blue", "b", "diffuse_blue"});
  if (pr && pg && pb) {
    const bool unit = pr->type == PlyType::kFloat32 || pr->type == PlyType::kFloat64;
    colors.resize(n);
    auto to8 = [&](double v) { return uint8_t(std::clamp(unit ? v * 255.0 + 0.5 : v, 0.0, 255.0)); };
    for (size_t i = 0; i < n; ++i) colors[i] = Rgb8{to8(pr->values[i]), to8(pg->values[i]), to8(pb->values[i])};
  }

  Scene scene;
  const PlyElement* face = ply.Find("face");
  if (face && face->count > 0) {
    const PlyProperty* idx = face->Find("vertex_indices");
    if (!idx) idx = face->Find("vertex_index");
    if (!idx || !idx->is_list)
      return Status::InvalidInput(FileError(path, "PLY face element lacks a vertex_indices list",
                                            "export faces as 'property list uchar int vertex_indices'"));
    Mesh& mesh = scene.mesh;
    mesh.vertices = std::move(positions);
    mesh.vertex_colors = std::move(colors);
    std::vector<std::pair<std::string, const PlyProperty*>> attrs;
    for (const auto& p : face->properties)
      if (!p.is_list) attrs.push_back({p.name, &p});
    for (auto& a : attrs) mesh.face_attributes[a.first].reserve(face->count);
    mesh.faces.reserve(face->count);
    for (size_t f = 0; f < face->count; ++f) {
      const uint32_t b = idx->list_offsets[f], e = idx->list_offsets[f + 1];
      if (e - b < 3) continue;  // Degenerate polygon: skipped.
      for (uint32_t k = b; k < e; ++k) {
        const double v = idx->list_values[k];
        if (v < 0 || v >= double(n))
          return Status::InvalidInput(FileError(path, "face " + std::to_string(f) + " uses vertex " +
                                                          std::to_string(int64_t(v)) + " but there are " +
                                                          std::to_string(n) + " vertices",
                                                "the file is corrupt"));
      }
      for (uint32_t k = b + 1; k + 1 < e; ++k) {  // Fan triangulation of polygons.
        mesh.faces.emplace_back(int(idx->list_values[b]), int(idx->list_values[k]), int(idx->list_values[k + 1]));
        for (auto& a : attrs) mesh.face_attributes[a.first].push_back(int32_t(a.second->values[f]));
      }
    }
    // Per-vertex texture coordinates with a "comment TextureFile NAME" (MeshLab convention).
    const PlyProperty* ps = find_any({"s", "texture_u", "u"});
    const PlyProperty* pt = find_any({"t", "texture_v", "v"});
    std::string texture_file;
    for (const auto& c : ply.comments)
      if (c.rfind("TextureFile ", 0) == 0) texture_file = c.substr(12);
    if (ps && pt && !texture_file.empty()) {
      const std::string tex_path = (std::filesystem::path(path).parent_path() / texture_file).string();
      Result<ImageRgb8> tex = ReadImageRgb8(tex_path);
      if (tex.ok()) {
        mesh.uvs.resize(n);
        for (size_t i = 0; i < n; ++i) mesh.uvs[i] = Eigen::Vector2f(float(ps->values[i]), float(pt->values[i]));
        Material m;
        m.name = "texture";
        m.texture = std::move(tex).value();
        m.texture_path = texture_file;
        mesh.materials.push_back(std::move(m));
        mesh.face_material.assign(mesh.faces.size(), 0);
      } else {
        SEMVOX_WARN(path << ": texture '" << texture_file << "' not loaded (" << tex.status().message()
                         << "); using vertex colours");
      }
    }
    if (mesh.faces.empty())
      return Status::InvalidInput(FileError(path, "all " + std::to_string(face->count) + " faces are degenerate",
                                            "the mesh has no usable triangles"));
  } else {
    PointCloud& cloud = scene.cloud;
    cloud.points = std::move(positions);
    cloud.colors = std::move(colors);
    const PlyProperty* nx = find_any({"nx"});
    const PlyProperty* ny = find_any({"ny"});
    const PlyProperty* nz = find_any({"nz"});
    if (nx && ny && nz) {
      cloud.normals.resize(n);
      for (size_t i = 0; i < n; ++i) {
        Eigen::Vector3f v(float(nx->values[i]), float(ny->values[i]), float(nz->values[i]));
        const float len = v.norm();
        cloud.normals[i] = len > 1e-12f && std::isfinite(len) ? Eigen::Vector3f(v / len) : Eigen::Vector3f::UnitZ();
      }
    }
    for (const char* attr : {"label", "instance", "room"})
      if (const PlyProperty* p = find_any({attr})) {
        auto& dst = cloud.point_attributes[attr];
        dst.resize(n);
        for (size_t i = 0; i < n; ++i) dst[i] = int32_t(p->values[i]);
      }
    if (n == 0)
      return Status::InvalidInput(FileError(path, "PLY has no vertices and no faces", "the file holds no geometry"));
  }
  return scene;
}

}  // namespace semvox
