#include "render/view_renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
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
  const int32_t* disc_point;         // Clouds with merged discs: Embree's primitive -> point index; else null.
  const int* face_material;          // kMaterial.
  const Material* materials;         // kMaterial.
  const Rgb8* point_colors;          // kCloud.
  const Mesh* mesh;                  // kTexture (Mesh::ColorAt).
  const FaceShade* face_shade;       // Meshes: one record per face.
  bool interpolate_corners;          // kVertex: corner colours differ on some faces.
  double inv_voxel_size;             // 1 / resolution, as OctoMap's coordToKey multiplies by it.
  double ox, oy, oz;                 // Camera centre, world frame (for cloud hits).
};

// One shaded 16x4 tile, laid out as the image rows it is copied into (row-major, 16 pixels a row, colour
// and normal channels interleaved), so that each row of each buffer leaves with one fixed-size copy.
struct ShadedTile {
  alignas(64) float depth[kTileHeight * kTileWidth];
  alignas(64) int32_t primitive[kTileHeight * kTileWidth];
  alignas(64) float normal[3 * kTileHeight * kTileWidth];
  alignas(64) VoxelKey key[kTileHeight * kTileWidth];
  alignas(64) uint8_t rgb[3 * kTileHeight * kTileWidth];
};

#pragma GCC diagnostic ignored "-Wpsabi"

// SIMD vectors of kBytes bytes (GCC vector extensions): arithmetic on them is lane-wise and compiles to
// SIMD instructions of whatever the enclosing function targets, with no reliance on the loop vectoriser.
// Shading runs with 32-byte vectors where the CPU has AVX2 and 16-byte (SSE2) ones elsewhere; both give
// the same bits (the same IEEE operations in the same order, no fused multiply-add).
template <int kBytes>
struct Simd {
  typedef float F __attribute__((vector_size(kBytes)));
  typedef int32_t I __attribute__((vector_size(kBytes)));
  typedef uint32_t U __attribute__((vector_size(kBytes)));
  typedef double D __attribute__((vector_size(kBytes)));
  typedef int64_t L __attribute__((vector_size(kBytes)));
  typedef float HalfF __attribute__((vector_size(kBytes / 2)));  // As many floats as D has doubles.
  typedef int32_t HalfI __attribute__((vector_size(kBytes / 2)));
  static constexpr int kFloats = kBytes / 4, kDoubles = kBytes / 8;
};

// Always inlined, so that no vector crosses a call (GCC's -Wpsabi note about vector ABIs does not apply;
// it is silenced for this file, above).
template <typename V, typename T>
inline __attribute__((always_inline)) V LoadVec(const T* p) {
  V v;
  std::memcpy(&v, p, sizeof(V));
  return v;
}
template <typename V, typename T>
inline __attribute__((always_inline)) void StoreVec(T* p, const V& v) {
  std::memcpy(p, &v, sizeof(V));
}

Rgb8 ScalarColor(const ShadeContext& c, int32_t prim, float u, float v) {
  switch (c.color_source) {
    case ColorSource::kMaterial: return c.materials[c.face_material[prim]].diffuse;
    case ColorSource::kTexture: return c.mesh->ColorAt(prim, u, v);
    case ColorSource::kCloud: return c.point_colors[prim];
    default: return Rgb8{200, 200, 200};
  }
}

// The per-pixel function, evaluated for the 16 lanes of a packet at once with kBytes-wide vectors; the
// packet's 4x4 pixels go to columns [col, col + 4) of `out`. Every output of a pixel follows from its own
// hit alone:
//   hit point   origin + t * direction (in double), except that on a face perpendicular to an axis that
//               coordinate is the face's own, so that points on walls, floors and ceilings lie on them
//               exactly (as the voxeliser sees them);
//   voxel key   floor(point / resolution) + 2^15 per axis, as OctoMap's coordToKey (multiplying by 1/res),
//               after moving the point up by kBoundaryToleranceVoxels as the voxeliser does;
//   normal      Embree's geometric normal, unit length, flipped to face the camera;
//   colour      Mesh::ColorAt (vertex colours interpolated inline), cloud colour or grey;
//   misses      black, depth 0, normal 0, primitive -1, key {0,0,0}.
// Returns the number of lanes that hit.
template <int kBytes>
inline __attribute__((always_inline)) int ShadePacketImpl(const ShadeContext& c, const RTCRayHit16& __restrict p,
                                                          const int* __restrict valid, int col,
                                                          ShadedTile* __restrict out) {
  using S = Simd<kBytes>;
  using F = typename S::F;
  using I = typename S::I;
  using U = typename S::U;
  using D = typename S::D;
  using L = typename S::L;
  constexpr int n = 16, nf = S::kFloats, nd = S::kDoubles;
  alignas(64) int32_t hit[n], prim[n];  // hit: -1 or 0; prim: 0 on a miss, so that gathers stay in range.
  for (int q = 0; q < n; q += nf) {
    const I h = (LoadVec<I>(valid + q) != 0) & (LoadVec<U>(p.hit.geomID + q) != RTC_INVALID_GEOMETRY_ID);
    StoreVec(hit + q, h);
    StoreVec(prim + q, h & LoadVec<I>(p.hit.primID + q));
  }
  if (c.disc_point)
    for (int l = 0; l < n; ++l) prim[l] = hit[l] ? c.disc_point[prim[l]] : 0;
  // Gather one 16-byte record per pixel; colours of uniform faces directly.
  alignas(64) float plane[n];
  alignas(64) int32_t axis[n];
  alignas(64) uint8_t rgb[3 * n];
  if (!c.is_cloud) {
    const bool interpolate = c.interpolate_corners;
    for (int l = 0; l < n; ++l) {
      const FaceShade& f = c.face_shade[prim[l]];
      plane[l] = f.plane;
      axis[l] = f.axis;
      if (f.uniform || !interpolate) {
        rgb[3 * l] = f.rgb[0], rgb[3 * l + 1] = f.rgb[1], rgb[3 * l + 2] = f.rgb[2];
      } else {  // = lround() of Mesh::ColorAt's interpolation for values >= 0.
        const float u = p.hit.u[l], v = p.hit.v[l], w = 1.0f - u - v;
        for (int k = 0; k < 3; ++k)
          rgb[3 * l + k] = uint8_t(std::min(std::max(w * f.rgb[k] + u * f.rgb[3 + k] + v * f.rgb[6 + k] + 0.5f, 0.0f), 255.0f));
      }
    }
  } else {
    for (int l = 0; l < n; ++l) plane[l] = 0, axis[l] = 3;
  }
  if (!(c.color_source == ColorSource::kVertex || c.color_source == ColorSource::kMaterial ||
        c.color_source == ColorSource::kGrey)) {
    for (int l = 0; l < n; ++l) {
      // Not for misses: their u and v are whatever the lane held before, and a texture lookup needs sane ones.
      const Rgb8 rc = hit[l] ? ScalarColor(c, prim[l], p.hit.u[l], p.hit.v[l]) : Rgb8{0, 0, 0};
      rgb[3 * l] = rc.r, rgb[3 * l + 1] = rc.g, rgb[3 * l + 2] = rc.b;
    }
  }

  // Hit points in double, then keys. Scaled coordinates are clamped to +-2^30 first, so that the
  // conversion is defined; anything that far out is outside OctoMap's key range anyway.
  constexpr double kClamp = 1073741824.0;                  // 2^30.
  constexpr double kRoundMagic = 6755399441055744.0;       // 1.5 * 2^52.
  const double inv = c.inv_voxel_size;
  const double tolerance = kBoundaryToleranceVoxels / inv;
  alignas(64) int32_t key[3][n];
  const double origin[3] = {c.ox, c.oy, c.oz};
  const float* dir[3] = {p.ray.dir_x, p.ray.dir_y, p.ray.dir_z};
  for (int q = 0; q < n; q += nd) {
    const D t = __builtin_convertvector(LoadVec<typename S::HalfF>(p.ray.tfar + q), D);
    const L ax = __builtin_convertvector(LoadVec<typename S::HalfI>(axis + q), L);
    const D pl = __builtin_convertvector(LoadVec<typename S::HalfF>(plane + q), D);
    for (int a = 0; a < 3; ++a) {
      D coord = origin[a] + t * __builtin_convertvector(LoadVec<typename S::HalfF>(dir[a] + q), D);
      coord = ax == a ? pl : coord;
      D s = inv * (coord + tolerance);
      s = s < -kClamp ? -kClamp : s;
      s = s > kClamp ? kClamp : s;
      // floor(s), exactly, in double lanes: adding and taking away 1.5 * 2^52 rounds s to the nearest
      // integer (every double in [2^52, 2^53) is an integer, and |s| <= 2^30); one down where that
      // rounded up. Then the conversion to int32 is exact.
      const D nearest = (s + kRoundMagic) - kRoundMagic;
      const D fl = nearest > s ? nearest - 1.0 : nearest;
      StoreVec(key[a] + q, __builtin_convertvector(fl, typename S::HalfI) + kKeyOffset);
    }
  }
  alignas(64) float depth[n], nrm[3][n];
  alignas(64) int32_t primitive[n];
  for (int q = 0; q < n; q += nf) {
    const I h = LoadVec<I>(hit + q);
    const I kx = LoadVec<I>(key[0] + q), ky = LoadVec<I>(key[1] + q), kz = LoadVec<I>(key[2] + q);
    const I ok = h & (U(kx) < 65536u) & (U(ky) < 65536u) & (U(kz) < 65536u);
    StoreVec(key[0] + q, kx & ok);
    StoreVec(key[1] + q, ky & ok);
    StoreVec(key[2] + q, kz & ok);
    // Normals. Branch-free: which side a face is seen from is as good as random. Misses are selected
    // to +0 rather than multiplied by 0: Embree leaves Ng of a missed lane as it was (stale or
    // uninitialised), and 0 times that could be -0 or NaN.
    const F nx = LoadVec<F>(p.hit.Ng_x + q), ny = LoadVec<F>(p.hit.Ng_y + q), nz = LoadVec<F>(p.hit.Ng_z + q);
    const F dx = LoadVec<F>(p.ray.dir_x + q), dy = LoadVec<F>(p.ray.dir_y + q), dz = LoadVec<F>(p.ray.dir_z + q);
    const F n2 = nx * nx + ny * ny + nz * nz;
    const F facing = nx * dx + ny * dy + nz * dz;
    F len = n2 > 1e-30f ? n2 : 1e-30f;
    for (int l = 0; l < nf; ++l) len[l] = std::sqrt(len[l]);  // sqrtps (no errno in this file).
    const F sign = facing > 0 ? F{} - 1.0f : F{} + 1.0f;  // Faces the camera.
    const F scale = sign * (1.0f / len);
    StoreVec(nrm[0] + q, h ? nx * scale : F{});
    StoreVec(nrm[1] + q, h ? ny * scale : F{});
    StoreVec(nrm[2] + q, h ? nz * scale : F{});
    StoreVec(depth + q, h ? LoadVec<F>(p.ray.tfar + q) : F{});
    StoreVec(primitive + q, h ? LoadVec<I>(prim + q) : I{} - 1);
  }

  // Misses are black.
  for (int l = 0; l < n; ++l) {
    const uint8_t m = uint8_t(hit[l]);  // 0xFF or 0.
    rgb[3 * l] &= m, rgb[3 * l + 1] &= m, rgb[3 * l + 2] &= m;
  }

  // The packet's rows (4 pixels each) into the tile's rows: interleaved channels by shuffles.
  typedef float F4 __attribute__((vector_size(16)));
  typedef uint16_t K4 __attribute__((vector_size(8)));
  typedef int32_t I4 __attribute__((vector_size(16)));
  for (int row = 0; row < kPacketSide; ++row) {
    const int l = row * kPacketSide, i = row * kTileWidth + col;
    std::memcpy(&out->depth[i], &depth[l], kPacketSide * sizeof(float));
    std::memcpy(&out->primitive[i], &primitive[l], kPacketSide * sizeof(int32_t));
    std::memcpy(&out->rgb[3 * i], &rgb[3 * l], 3 * kPacketSide);
    // (x0..x3), (y0..y3), (z0..z3) -> x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3.
    const F4 x = LoadVec<F4>(nrm[0] + l), y = LoadVec<F4>(nrm[1] + l), z = LoadVec<F4>(nrm[2] + l);
    const F4 xy01 = __builtin_shufflevector(x, y, 0, 4, 1, 5), xy23 = __builtin_shufflevector(x, y, 2, 6, 3, 7);
    const F4 yz1 = __builtin_shufflevector(xy01, z, 3, 5, 3, 5);
    StoreVec(&out->normal[3 * i], __builtin_shufflevector(xy01, z, 0, 1, 4, 2));
    StoreVec(&out->normal[3 * i + 4], __builtin_shufflevector(yz1, xy23, 0, 1, 4, 5));
    StoreVec(&out->normal[3 * i + 8], __builtin_shufflevector(xy23, z, 6, 2, 3, 7));
    // Keys: the low 16 bits of each index (all in range or 0 by now), interleaved the same way.
    const K4 kx = __builtin_convertvector(LoadVec<I4>(key[0] + l), K4);
    const K4 ky = __builtin_convertvector(LoadVec<I4>(key[1] + l), K4);
    const K4 kz = __builtin_convertvector(LoadVec<I4>(key[2] + l), K4);
    const auto kxy = __builtin_shufflevector(kx, ky, 0, 1, 2, 3, 4, 5, 6, 7);
    const auto kzz = __builtin_shufflevector(kz, kz, 0, 1, 2, 3, 0, 1, 2, 3);
    uint16_t* kd = reinterpret_cast<uint16_t*>(&out->key[i]);
    StoreVec(kd, __builtin_shufflevector(kxy, kzz, 0, 4, 8, 1, 5, 9, 2, 6));
    StoreVec(kd + 8, __builtin_shufflevector(kxy, kzz, 10, 3, 7, 11));
  }
  int hits = 0;
  for (int l = 0; l < n; ++l) hits -= hit[l];
  return hits;
}

__attribute__((target("avx2"))) int ShadePacketAvx2(const ShadeContext& c, const RTCRayHit16& p, const int* valid,
                                                    int col, ShadedTile* out) {
  return ShadePacketImpl<32>(c, p, valid, col, out);
}
int ShadePacketSse2(const ShadeContext& c, const RTCRayHit16& p, const int* valid, int col, ShadedTile* out) {
  return ShadePacketImpl<16>(c, p, valid, col, out);
}

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
  ctx.disc_point = rc.disc_point.empty() ? nullptr : rc.disc_point.data();
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
  // World-frame ray directions (camera-frame z = 1) split into a per-column and a per-row part:
  // direction = rot * (x, y, 1) = col_part[x] + row_part[y] with col_part = rot.col(0) x and row_part =
  // rot.col(1) y + rot.col(2), the association the product was always evaluated in (float, no fused
  // multiply-add), so the directions are the same bits. Padded by kPacketSide - 1 copies of the last column
  // and row, so that a packet reaching past the image repeats its edge pixel without a branch.
  std::array<std::vector<float>, 3> col_part, row_part;
  for (int a = 0; a < 3; ++a) {
    col_part[size_t(a)].resize(size_t(w + kPacketSide - 1));
    row_part[size_t(a)].resize(size_t(h + kPacketSide - 1));
  }
  for (int x = 0; x < w + kPacketSide - 1; ++x) {
    const float xs = float((std::min(x, w - 1) + 0.5 - camera.cx) / camera.fx);
    for (int a = 0; a < 3; ++a) col_part[size_t(a)][size_t(x)] = rot(a, 0) * xs;
  }
  for (int y = 0; y < h + kPacketSide - 1; ++y) {
    const float ys = float((std::min(y, h - 1) + 0.5 - camera.cy) / camera.fy);
    for (int a = 0; a < 3; ++a) row_part[size_t(a)][size_t(y)] = rot(a, 1) * ys + rot(a, 2);
  }
  const float tfar = float(options.max_depth_m);
  const int tiles_x = (w + kTileWidth - 1) / kTileWidth, tiles_y = (h + kTileHeight - 1) / kTileHeight;
  std::atomic<size_t> hit_pixels{0};
  static const bool use_avx2 = __builtin_cpu_supports("avx2");

  tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y), [&](const tbb::blocked_range<int>& range) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRayHit16 packet;
    alignas(64) int valid[16];
    // What every ray of every packet shares; Embree writes only tfar and the hit fields.
    for (int lane = 0; lane < 16; ++lane) {
      packet.ray.org_x[lane] = org.x();
      packet.ray.org_y[lane] = org.y();
      packet.ray.org_z[lane] = org.z();
      packet.ray.tnear[lane] = 0.0f;
      packet.ray.time[lane] = 0.0f;
      packet.ray.mask[lane] = 0xFFFFFFFFu;
      packet.ray.id[lane] = unsigned(lane);
      packet.ray.flags[lane] = 0;
    }
    const float* const col_x = col_part[0].data();
    const float* const col_y = col_part[1].data();
    const float* const col_z = col_part[2].data();
    const ShadeContext c = ctx;
    const bool avx2 = use_avx2;
    ShadedTile shaded;
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
        for (int row = 0; row < kPacketSide; ++row) {
          const int y = sy + row;
          const float ry = row_part[0][size_t(y)], ryy = row_part[1][size_t(y)], ryz = row_part[2][size_t(y)];
          for (int col = 0; col < kPacketSide; ++col) {  // Vectorised: 4 lanes of one packet row.
            const int lane = row * kPacketSide + col;
            valid[lane] = (sx + col < w && y < h) ? -1 : 0;
            packet.ray.dir_x[lane] = col_x[sx + col] + ry;
            packet.ray.dir_y[lane] = col_y[sx + col] + ryy;
            packet.ray.dir_z[lane] = col_z[sx + col] + ryz;
            packet.ray.tfar[lane] = tfar;
            packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
            packet.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
          }
        }
        // Traced as two 8-ray packets (rows 0-1 and 2-3): 8 lanes are AVX2's native packet width, and on the
        // 2-core AVX2 development machine this, copies included, beat one 16-ray call (render_bench: full
        // render per CPU second +11-15 %). The same hits bit for bit (render_bench's checksums, whole runs).
        for (int half = 0; half < 2; ++half) {
          alignas(32) RTCRayHit8 p8;
          alignas(32) int v8[8];
          const int o = 8 * half;
          for (int l = 0; l < 8; ++l) {
            v8[l] = valid[o + l];
            p8.ray.org_x[l] = packet.ray.org_x[o + l];
            p8.ray.org_y[l] = packet.ray.org_y[o + l];
            p8.ray.org_z[l] = packet.ray.org_z[o + l];
            p8.ray.dir_x[l] = packet.ray.dir_x[o + l];
            p8.ray.dir_y[l] = packet.ray.dir_y[o + l];
            p8.ray.dir_z[l] = packet.ray.dir_z[o + l];
            p8.ray.tnear[l] = packet.ray.tnear[o + l];
            p8.ray.tfar[l] = packet.ray.tfar[o + l];
            p8.ray.time[l] = packet.ray.time[o + l];
            p8.ray.mask[l] = packet.ray.mask[o + l];
            p8.ray.id[l] = packet.ray.id[o + l];
            p8.ray.flags[l] = packet.ray.flags[o + l];
            p8.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
            p8.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
          }
          rtcIntersect8(v8, rc.scene, &context, &p8);
          for (int l = 0; l < 8; ++l) {
            packet.ray.tfar[o + l] = p8.ray.tfar[l];
            packet.hit.geomID[o + l] = p8.hit.geomID[l];
            packet.hit.primID[o + l] = p8.hit.primID[l];
            packet.hit.u[o + l] = p8.hit.u[l];
            packet.hit.v[o + l] = p8.hit.v[l];
            packet.hit.Ng_x[o + l] = p8.hit.Ng_x[l];
            packet.hit.Ng_y[o + l] = p8.hit.Ng_y[l];
            packet.hit.Ng_z[o + l] = p8.hit.Ng_z[l];
          }
        }
        const int col = sub * kPacketSide;
        local_hits += size_t(avx2 ? ShadePacketAvx2(c, packet, valid, col, &shaded)
                                  : ShadePacketSse2(c, packet, valid, col, &shaded));
      }
      // Copy the tile's rows into the images: fixed-size copies for whole tiles.
      const int rows = std::min(kTileHeight, h - ty0), cols = std::min(kTileWidth, w - tx0);
      for (int row = 0; row < rows; ++row) {
        const size_t idx = size_t(ty0 + row) * w + tx0;
        const int t = row * kTileWidth;
        if (cols == kTileWidth) {
          std::memcpy(depth + idx, &shaded.depth[t], kTileWidth * sizeof(float));
          std::memcpy(primitive + idx, &shaded.primitive[t], kTileWidth * sizeof(int32_t));
          std::memcpy(normal + 3 * idx, &shaded.normal[3 * t], 3 * kTileWidth * sizeof(float));
          std::memcpy(key + idx, &shaded.key[t], kTileWidth * sizeof(VoxelKey));
          std::memcpy(rgb + 3 * idx, &shaded.rgb[3 * t], 3 * kTileWidth);
        } else {
          std::memcpy(depth + idx, &shaded.depth[t], cols * sizeof(float));
          std::memcpy(primitive + idx, &shaded.primitive[t], cols * sizeof(int32_t));
          std::memcpy(normal + 3 * idx, &shaded.normal[3 * t], 3 * cols * sizeof(float));
          std::memcpy(key + idx, &shaded.key[t], cols * sizeof(VoxelKey));
          std::memcpy(rgb + 3 * idx, &shaded.rgb[3 * t], 3 * cols);
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
