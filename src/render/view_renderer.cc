#include "render/view_renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <sstream>

#include "render/embree_scene.h"

namespace semvox {
namespace {

constexpr int kTileWidth = 16;  // Pixels per tile: four 4x4 packets of 16 rays side by side, so that each
constexpr int kTileHeight = 4;  // tile row is one 64-byte line of depth and of primitive ids.
constexpr int kPacketSide = 4;  // 16 = 4 x 4 rays per rtcIntersect16 packet.
constexpr int kPrefetchTiles = 2;  // How far ahead the image lines of coming tiles are fetched.
// Keys follow the voxeliser's half-open cells (mapping/voxelizer.cc, VoxelizeMeshSurface): a surface up to
// this fraction of a voxel below a voxel boundary belongs to the voxel above it. Walls on round
// coordinates are stored as floats a hair below them (1.9f = 1.89999998), and without the same tolerance
// their pixels would get the free voxel next to the occupied one.
constexpr double kBoundaryToleranceVoxels = 1e-4;

// Where pixel colours come from, decided once per scene: the general Mesh::ColorAt for textured meshes,
// and inlined equivalents of its other branches (vertex colours, material colours, grey), which are the
// same colours without a call and a libm lround per pixel.
enum class ColorSource { kTexture, kVertex, kMaterial, kGrey, kCloud, kCloudGrey };

ColorSource ChooseColorSource(const Scene& scene) {
  if (!scene.is_mesh()) return scene.cloud.has_colors() ? ColorSource::kCloud : ColorSource::kCloudGrey;
  const Mesh& m = scene.mesh;
  if (m.has_texture()) return ColorSource::kTexture;
  if (m.has_vertex_colors()) return ColorSource::kVertex;
  if (!m.face_material.empty()) return ColorSource::kMaterial;
  return ColorSource::kGrey;
}

// What a mesh pixel needs of its face beyond Embree's hit, packed in 16 bytes so that shading costs one
// cache line per pixel on large meshes (Embree keeps its own copy of the geometry, so the mesh arrays are
// cold): the corner colours (kVertex, kMaterial, kGrey) and, for a face perpendicular to an axis, its
// coordinate along that axis, so that hit points on it lie on it exactly.
struct FaceShade {
  float plane = 0;      // The face's coordinate along `axis`.
  uint8_t axis = 3;     // 0, 1, 2: all three vertices share that coordinate exactly; 3: none.
  uint8_t rgb[9] = {};  // Corner colours (r, g, b) x 3.
  uint8_t uniform = 0;  // 1 when the three corner colours are equal (no interpolation needed).
  uint8_t pad = 0;
};
static_assert(sizeof(FaceShade) == 16);

// What shading reads, as plain pointers loaded once per task: the 8-bit colour stores below may alias
// anything, so reaching the data through the scene and vector objects would reload it after every store.
struct ShadeContext {
  ColorSource color_source;
  bool is_cloud;
  const int* face_material;          // kMaterial.
  const Material* materials;         // kMaterial.
  const Rgb8* point_colors;          // kCloud.
  const Mesh* mesh;                  // kTexture (Mesh::ColorAt).
  const FaceShade* face_shade;       // Meshes: one record per face.
  bool interpolate_corners;          // kVertex: corner colours differ on some faces.
  double inv_voxel_size;             // 1 / resolution, as OctoMap's coordToKey multiplies by it.
  double ox, oy, oz;                 // Camera centre, world frame (for cloud hits).
};

// One shaded 4x4 packet as structure of arrays, lane = 4 * row + column.
struct ShadedPacket {
  alignas(64) float depth[16];
  alignas(64) float nx[16], ny[16], nz[16];
  alignas(64) int32_t primitive[16];
  alignas(64) int32_t kx[16], ky[16], kz[16];  // Key indices; all 0 for pixels without a (valid) key.
  alignas(64) uint8_t rgb[48];
  int hits = 0;
};

Rgb8 ScalarColor(const ShadeContext& c, int32_t prim, float u, float v) {
  switch (c.color_source) {
    case ColorSource::kMaterial: return c.materials[c.face_material[prim]].diffuse;
    case ColorSource::kTexture: return c.mesh->ColorAt(prim, u, v);
    case ColorSource::kCloud: return c.point_colors[prim];
    default: return Rgb8{200, 200, 200};
  }
}

}  // namespace

// The per-pixel function, evaluated for the 16 lanes of a packet at once: gathers first, then plain
// loops over arrays that the compiler vectorises (an AVX2 clone is picked at run time where the CPU has
// it). Every output of a pixel follows from its own hit alone:
//   hit point   on the face from the barycentrics (exact for axis-aligned faces, as Raycaster::HitPoint),
//               or origin + t * direction for cloud discs;
//   voxel key   floor(point / resolution) + 2^15 per axis, as OctoMap's coordToKey (multiplying by 1/res),
//               after moving the point up by kBoundaryToleranceVoxels as the voxeliser does;
//   normal      Embree's geometric normal, unit length, flipped to face the camera;
//   colour      Mesh::ColorAt (vertex colours interpolated inline), cloud colour or grey;
//   misses      black, depth 0, normal 0, primitive -1, key {0,0,0}.
__attribute__((target_clones("avx2", "default")))
void ShadePacket(const ShadeContext& c, const RTCRayHit16& __restrict p, const int* __restrict valid,
                 ShadedPacket* __restrict out) {
  constexpr int n = 16;
  alignas(64) int32_t hit[n];  // 1 or 0.
  alignas(64) int32_t prim[n];
  int hits = 0;
  for (int l = 0; l < n; ++l) {
    hit[l] = valid[l] != 0 && p.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID;
    prim[l] = hit[l] ? int32_t(p.hit.primID[l]) : 0;
    hits += hit[l];
  }
  out->hits = hits;
  // Hit points: origin + t * direction, then on a face perpendicular to an axis that coordinate is the
  // face's own, so points on walls, floors and ceilings lie on them exactly (as the voxeliser sees them).
  alignas(64) double px[n], py[n], pz[n];
  for (int l = 0; l < n; ++l) {
    const double t = p.ray.tfar[l];
    px[l] = c.ox + t * p.ray.dir_x[l];
    py[l] = c.oy + t * p.ray.dir_y[l];
    pz[l] = c.oz + t * p.ray.dir_z[l];
  }
  alignas(64) float plane[n];
  alignas(64) int32_t axis[n];
  alignas(64) uint8_t rgb[3 * n];
  if (!c.is_cloud) {
    for (int l = 0; l < n; ++l) {  // Gather one 16-byte record per pixel; colours of uniform faces directly.
      const FaceShade& f = c.face_shade[prim[l]];
      plane[l] = f.plane;
      axis[l] = f.axis;
      if (f.uniform || !c.interpolate_corners) {
        rgb[3 * l] = f.rgb[0], rgb[3 * l + 1] = f.rgb[1], rgb[3 * l + 2] = f.rgb[2];
      } else {  // = lround() of Mesh::ColorAt's interpolation for values >= 0.
        const float u = p.hit.u[l], v = p.hit.v[l], w = 1.0f - u - v;
        for (int k = 0; k < 3; ++k)
          rgb[3 * l + k] = uint8_t(std::min(std::max(w * f.rgb[k] + u * f.rgb[3 + k] + v * f.rgb[6 + k] + 0.5f, 0.0f), 255.0f));
      }
    }
    for (int l = 0; l < n; ++l) {
      px[l] = axis[l] == 0 ? double(plane[l]) : px[l];
      py[l] = axis[l] == 1 ? double(plane[l]) : py[l];
      pz[l] = axis[l] == 2 ? double(plane[l]) : pz[l];
    }
  }
  // Keys. Scaled coordinates are clamped to +-2^30 first, so that the conversion is defined; anything
  // that far out is outside OctoMap's key range anyway.
  constexpr double kClamp = 1073741824.0;
  const double inv = c.inv_voxel_size;
  const double tolerance = kBoundaryToleranceVoxels / inv;
  const auto key_index = [&](double coord) {
    double s = inv * (coord + tolerance);
    s = s < -kClamp ? -kClamp : s;  // Value selects (not std::clamp's references) so the loop vectorises.
    s = s > kClamp ? kClamp : s;
    const int32_t i = int32_t(s);  // Truncation; floor below.
    return i - int32_t(s < double(i)) + int32_t(kKeyOffset);
  };
  for (int l = 0; l < n; ++l) out->kx[l] = key_index(px[l]);
  for (int l = 0; l < n; ++l) out->ky[l] = key_index(py[l]);
  for (int l = 0; l < n; ++l) out->kz[l] = key_index(pz[l]);
  for (int l = 0; l < n; ++l) {
    const bool ok = hit[l] && uint32_t(out->kx[l]) < 65536u && uint32_t(out->ky[l]) < 65536u &&
                    uint32_t(out->kz[l]) < 65536u;
    out->kx[l] = ok ? out->kx[l] : 0;
    out->ky[l] = ok ? out->ky[l] : 0;
    out->kz[l] = ok ? out->kz[l] : 0;
  }
  for (int l = 0; l < n; ++l) {  // Branch-free: which side a face is seen from is as good as random.
    const float nx = p.hit.Ng_x[l], ny = p.hit.Ng_y[l], nz = p.hit.Ng_z[l];
    const float n2 = nx * nx + ny * ny + nz * nz;
    const float facing = nx * p.ray.dir_x[l] + ny * p.ray.dir_y[l] + nz * p.ray.dir_z[l];
    const float inv_len = 1.0f / std::sqrt(n2 > 1e-30f ? n2 : 1e-30f);
    const float sign = facing > 0 ? -1.0f : 1.0f;         // Faces the camera.
    const float scale = sign * inv_len * float(hit[l]);   // 0 on a miss.
    out->nx[l] = nx * scale;
    out->ny[l] = ny * scale;
    out->nz[l] = nz * scale;
    out->depth[l] = p.ray.tfar[l] * float(hit[l]);
  }
  for (int l = 0; l < n; ++l) out->primitive[l] = hit[l] ? prim[l] : -1;
  if (c.color_source == ColorSource::kVertex || c.color_source == ColorSource::kMaterial ||
      c.color_source == ColorSource::kGrey) {
    for (int l = 0; l < n; ++l)
      for (int k = 0; k < 3; ++k) out->rgb[3 * l + k] = hit[l] ? rgb[3 * l + k] : 0;
  } else {
    for (int l = 0; l < n; ++l) {
      const Rgb8 col = hit[l] ? ScalarColor(c, prim[l], p.hit.u[l], p.hit.v[l]) : Rgb8{0, 0, 0};
      out->rgb[3 * l] = col.r, out->rgb[3 * l + 1] = col.g, out->rgb[3 * l + 2] = col.b;
    }
  }
}

namespace {

template <typename T>
void Resize(Image<T>* image, int w, int h, int c) {
  if (image->width == w && image->height == h && image->channels == c) return;
  *image = Image<T>(w, h, c);
}

}  // namespace

bool RenderOptions::Check(std::string* error) const {
  std::ostringstream os;
  if (!(voxel_size_m >= 0.001 && voxel_size_m <= 10))
    os << "voxel_size_m = " << voxel_size_m << ". Violated constraint: 0.001 <= voxel_size_m <= 10";
  else if (!(max_depth_m > 0) || std::isnan(max_depth_m))
    os << "max_depth_m = " << max_depth_m << ". Violated constraint: max_depth_m > 0";
  if (os.str().empty()) return true;
  if (error) *error = os.str();
  return false;
}

struct ViewRenderer::ShadeData {
  std::vector<FaceShade> faces;
};

Result<ViewRenderer> ViewRenderer::Create(const Scene& scene, const RaycasterOptions& options) {
  Result<Raycaster> rc = Raycaster::FromScene(scene, options);
  if (!rc.ok()) return rc.status();
  auto shade = std::make_shared<ShadeData>();
  if (scene.is_mesh()) {
    const Mesh& m = scene.mesh;
    const ColorSource source = ChooseColorSource(scene);
    shade->faces.resize(m.faces.size());
    for (size_t i = 0; i < m.faces.size(); ++i) {
      const Eigen::Vector3i& f = m.faces[i];
      FaceShade& r = shade->faces[i];
      for (int axis = 0; axis < 3 && r.axis == 3; ++axis) {
        const float c0 = m.vertices[f[0]][axis];
        if (m.vertices[f[1]][axis] == c0 && m.vertices[f[2]][axis] == c0) r.axis = uint8_t(axis), r.plane = c0;
      }
      for (int corner = 0; corner < 3; ++corner) {
        Rgb8 c{200, 200, 200};
        if (source == ColorSource::kVertex) c = m.vertex_colors[f[corner]];
        else if (source == ColorSource::kMaterial) c = m.materials[m.face_material[i]].diffuse;
        r.rgb[3 * corner] = c.r, r.rgb[3 * corner + 1] = c.g, r.rgb[3 * corner + 2] = c.b;
      }
      r.uniform = std::equal(r.rgb, r.rgb + 3, r.rgb + 3) && std::equal(r.rgb, r.rgb + 3, r.rgb + 6);
    }
  }
  return ViewRenderer(&scene, std::move(rc).value(), std::move(shade));
}

Status ViewRenderer::Render(const PinholeCamera& camera, const Eigen::Isometry3d& world_from_camera,
                            const RenderOptions& options, RenderedView* view) const {
  std::string error;
  if (!camera.Check(&error)) return Status::InvalidInput("camera: " + error);
  if (!options.Check(&error)) return Status::InvalidInput("render options: " + error);
  if (!world_from_camera.matrix().allFinite()) return Status::InvalidInput("camera pose is not finite");
  const int w = camera.width, h = camera.height;
  view->camera = camera;
  view->world_from_camera = world_from_camera;
  Resize(&view->rgb, w, h, 3);
  Resize(&view->depth, w, h, 1);
  Resize(&view->normal, w, h, 3);
  Resize(&view->primitive, w, h, 1);
  Resize(&view->voxel_key, w, h, 1);

  const Raycaster::Impl& rc = raycaster_.impl();
  ShadeContext ctx{};
  ctx.color_source = ChooseColorSource(*scene_);
  ctx.is_cloud = rc.is_cloud;
  ctx.face_material = scene_->mesh.face_material.data();
  ctx.materials = scene_->mesh.materials.data();
  ctx.point_colors = scene_->cloud.colors.data();
  ctx.mesh = &scene_->mesh;
  ctx.face_shade = shade_->faces.data();
  ctx.interpolate_corners = ctx.color_source == ColorSource::kVertex;
  ctx.inv_voxel_size = 1.0 / options.voxel_size_m;
  ctx.ox = world_from_camera.translation().x();
  ctx.oy = world_from_camera.translation().y();
  ctx.oz = world_from_camera.translation().z();
  const Eigen::Matrix3f rot = world_from_camera.linear().cast<float>();
  const Eigen::Vector3f org = world_from_camera.translation().cast<float>();
  // Camera-frame ray coordinates per column and row (z = 1).
  std::vector<float> xs(camera.width), ys(camera.height);
  for (int x = 0; x < camera.width; ++x) xs[x] = float((x + 0.5 - camera.cx) / camera.fx);
  for (int y = 0; y < camera.height; ++y) ys[y] = float((y + 0.5 - camera.cy) / camera.fy);
  const float tfar = float(options.max_depth_m);
  const int tiles_x = (w + kTileWidth - 1) / kTileWidth, tiles_y = (h + kTileHeight - 1) / kTileHeight;
  std::atomic<size_t> hit_pixels{0};

  tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y), [&](const tbb::blocked_range<int>& range) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRayHit16 packet;
    alignas(64) int valid[16];
    const ShadeContext c = ctx;
    ShadedPacket shaded;
    float* __restrict depth = view->depth.data.data();
    float* __restrict normal = view->normal.data.data();
    int32_t* __restrict primitive = view->primitive.data.data();
    VoxelKey* __restrict key = view->voxel_key.data.data();
    uint8_t* __restrict rgb = view->rgb.data.data();
    size_t local_hits = 0;
    for (int tile = range.begin(); tile != range.end(); ++tile) {
      const int tx0 = (tile % tiles_x) * kTileWidth, ty0 = (tile / tiles_x) * kTileHeight;
      // The image rows of a coming tile are cold (9 MB of buffers per view): fetch their cache lines
      // while this tile is traced, so that its stores do not wait for memory.
      if (tile + kPrefetchTiles < range.end()) {
        const int next = tile + kPrefetchTiles;
        const int nx0 = (next % tiles_x) * kTileWidth, ny0 = (next / tiles_x) * kTileHeight;
        for (int row = ny0; row < std::min(ny0 + kTileHeight, h); ++row) {
          const size_t i = size_t(row) * w + nx0;
          // First and last element of each buffer's run (the runs need not start on a line).
          __builtin_prefetch(depth + i, 1);
          __builtin_prefetch(depth + i + kTileWidth - 1, 1);
          __builtin_prefetch(primitive + i, 1);
          __builtin_prefetch(primitive + i + kTileWidth - 1, 1);
          for (int k = 0; k < 3 * kTileWidth; k += 16) __builtin_prefetch(normal + 3 * i + k, 1);
          __builtin_prefetch(normal + 3 * i + 3 * kTileWidth - 1, 1);
          for (int k = 0; k < kTileWidth; k += 10) __builtin_prefetch(key + i + k, 1);
          __builtin_prefetch(key + i + kTileWidth - 1, 1);
          __builtin_prefetch(rgb + 3 * i, 1);
          __builtin_prefetch(rgb + 3 * i + 3 * kTileWidth - 1, 1);
        }
      }
      for (int sub = 0; sub < kTileWidth / kPacketSide; ++sub) {
        const int sx = tx0 + sub * kPacketSide, sy = ty0;
        if (sx >= w || sy >= h) continue;
        for (int lane = 0; lane < 16; ++lane) {
          const int px = std::min(sx + lane % kPacketSide, w - 1), py = std::min(sy + lane / kPacketSide, h - 1);
          valid[lane] = (sx + lane % kPacketSide < w && sy + lane / kPacketSide < h) ? -1 : 0;
          // Camera-frame direction with z = 1: the ray parameter of a hit is its depth.
          const Eigen::Vector3f d = rot * Eigen::Vector3f(xs[px], ys[py], 1.0f);
          packet.ray.org_x[lane] = org.x();
          packet.ray.org_y[lane] = org.y();
          packet.ray.org_z[lane] = org.z();
          packet.ray.dir_x[lane] = d.x();
          packet.ray.dir_y[lane] = d.y();
          packet.ray.dir_z[lane] = d.z();
          packet.ray.tnear[lane] = 0.0f;
          packet.ray.tfar[lane] = tfar;
          packet.ray.time[lane] = 0.0f;
          packet.ray.mask[lane] = 0xFFFFFFFFu;
          packet.ray.id[lane] = unsigned(lane);
          packet.ray.flags[lane] = 0;
          packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
          packet.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect16(valid, rc.scene, &context, &packet);
        ShadePacket(c, packet, valid, &shaded);
        local_hits += size_t(shaded.hits);
        // Interleave the packet's rows into the images (4 contiguous pixels per row).
        const int cols = std::min(kPacketSide, w - sx);
        for (int row = 0; row < kPacketSide && sy + row < h; ++row) {
          const size_t idx = size_t(sy + row) * w + sx;
          const int l0 = row * kPacketSide;
          std::memcpy(depth + idx, &shaded.depth[l0], cols * sizeof(float));
          std::memcpy(primitive + idx, &shaded.primitive[l0], cols * sizeof(int32_t));
          for (int col = 0; col < cols; ++col) {
            const int l = l0 + col;
            const size_t i = idx + col;
            normal[3 * i] = shaded.nx[l];
            normal[3 * i + 1] = shaded.ny[l];
            normal[3 * i + 2] = shaded.nz[l];
            key[i] = VoxelKey{uint16_t(shaded.kx[l]), uint16_t(shaded.ky[l]), uint16_t(shaded.kz[l])};
          }
          std::memcpy(rgb + 3 * idx, &shaded.rgb[3 * l0], 3 * cols);
        }
      }
    }
    hit_pixels += local_hits;
  });
  view->hit_pixels = hit_pixels.load();
  return Status::Ok();
}

ImageRgb8 DownscaleImage(const ImageRgb8& image, int width) {
  if (width <= 0 || image.width <= width) return image;
  const int height = std::max(1, int(std::lround(double(image.height) * width / image.width)));
  ImageRgb8 out(width, height, image.channels);
  for (int y = 0; y < height; ++y) {
    const int y0 = y * image.height / height, y1 = std::max(y0 + 1, (y + 1) * image.height / height);
    for (int x = 0; x < width; ++x) {
      const int x0 = x * image.width / width, x1 = std::max(x0 + 1, (x + 1) * image.width / width);
      for (int c = 0; c < image.channels; ++c) {
        unsigned sum = 0;
        for (int yy = y0; yy < y1; ++yy)
          for (int xx = x0; xx < x1; ++xx) sum += image.at(xx, yy, c);
        out.at(x, y, c) = uint8_t(sum / unsigned((y1 - y0) * (x1 - x0)));
      }
    }
  }
  return out;
}

}  // namespace semvox
