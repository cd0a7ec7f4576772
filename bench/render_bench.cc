// Render throughput: the full view render (RGB, depth, normal, primitive id, voxel key) against a bare
// rtcIntersect16 loop over the same Embree scene, camera and poses, in the same run.
//
//   render_bench [--faces N ...] [--rounds R] [--threads T] [--views-per-position K] [--size WxH] [--checksum]
//
// The mesh is the bundled demo apartment with its longest edges bisected until it has about N faces
// (the nearer of the two refinement levels around N; default about 10 k and about 1 M). Poses: the automatic viewpoints of the demo apartment (render/views.h)
// with K yaws each. Bare and full alternate pose by pose (so both see the same load on a shared machine);
// each round sums both over all poses; the best round of each is reported, plus the median.
// With --threads 1 the rates per CPU second of the process are printed too: they do not depend on how
// much of the machine other jobs take, so the full/bare ratio is steadier on a shared machine.
// --checksum also prints an FNV-1a hash of every buffer of every full render (to check that a change to
// the renderer leaves its output bit for bit the same).
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <ctime>
#include <vector>

#include "io/load_scene.h"
#include "mapping/voxelizer.h"
#include "render/embree_scene.h"
#include "render/view_renderer.h"
#include "render/views.h"

namespace semvox {
namespace {

using Clock = std::chrono::steady_clock;

// Splits every face's longest edge at its midpoint (shared edges split once, so the mesh stays
// watertight) until the mesh has about `target` faces (the nearer of the two levels around it). Colours
// and attributes are dropped except vertex colours, which are interpolated.
Mesh Subdivide(Mesh mesh, size_t target) {
  mesh.uvs.clear();
  mesh.face_material.clear();
  mesh.materials.clear();
  mesh.face_attributes.clear();
  while (mesh.faces.size() < target) {
    const Mesh before = mesh;  // Kept to return whichever of the last two sizes is nearer the target.
    std::map<std::pair<int, int>, int> midpoint;
    std::vector<Eigen::Vector3i> faces;
    faces.reserve(mesh.faces.size() * 2);
    const auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      const int id = int(mesh.vertices.size());
      mesh.vertices.push_back(0.5f * (mesh.vertices[a] + mesh.vertices[b]));
      if (mesh.has_vertex_colors()) {
        const Rgb8 ca = mesh.vertex_colors[a], cb = mesh.vertex_colors[b];
        mesh.vertex_colors.push_back(Rgb8{uint8_t((ca.r + cb.r) / 2), uint8_t((ca.g + cb.g) / 2), uint8_t((ca.b + cb.b) / 2)});
      }
      midpoint.emplace(key, id);
      return id;
    };
    // Every face nominates its longest edge; each face is then split along all nominated edges it has
    // (1, 2 or 3, as in red-green refinement), so neighbours agree and no T-junction appears.
    std::map<std::pair<int, int>, bool> chosen;
    for (const auto& f : mesh.faces) {
      int best = 0;
      float best_len = -1;
      for (int e = 0; e < 3; ++e) {
        const float len = (mesh.vertices[f[(e + 1) % 3]] - mesh.vertices[f[e]]).squaredNorm();
        if (len > best_len) best_len = len, best = e;
      }
      chosen[std::minmax(f[best], f[(best + 1) % 3])] = true;
    }
    for (const auto& f : mesh.faces) {
      // Split along chosen edges: 0, 1, 2 or 3 of them (like red-green refinement).
      int m[3];
      int count = 0;
      for (int e = 0; e < 3; ++e) {
        m[e] = chosen.count(std::minmax(f[e], f[(e + 1) % 3])) ? mid(f[e], f[(e + 1) % 3]) : -1;
        count += m[e] >= 0;
      }
      if (count == 0) {
        faces.push_back(f);
      } else if (count == 3) {
        faces.push_back({f[0], m[0], m[2]});
        faces.push_back({m[0], f[1], m[1]});
        faces.push_back({m[2], m[1], f[2]});
        faces.push_back({m[0], m[1], m[2]});
      } else {
        // Rotate so that edge 0 is split; fan from its midpoint.
        int r = 0;
        while (m[r] < 0) ++r;
        const int a = f[r], b = f[(r + 1) % 3], c = f[(r + 2) % 3];
        const int mab = m[r], mbc = m[(r + 1) % 3], mca = m[(r + 2) % 3];
        faces.push_back({mab, b, mbc >= 0 ? mbc : c});
        if (mbc >= 0) faces.push_back({mab, mbc, c});
        if (mca >= 0) {
          faces.push_back({mab, c, mca});
          faces.push_back({mab, mca, a});
        } else {
          faces.push_back({mab, c, a});
        }
      }
    }
    mesh.faces.swap(faces);
    if (mesh.faces.size() >= target && mesh.faces.size() - target > target - before.faces.size()) return before;
  }
  return mesh;
}

struct Pose {
  Eigen::Isometry3d world_from_camera;
};

// The bare loop: the same tiles, packets and camera rays as ViewRenderer::Render, and nothing else.
size_t BareRender(const Raycaster& rc, const PinholeCamera& camera, const Eigen::Isometry3d& world_from_camera,
                  float max_depth) {
  const RTCScene scene = rc.impl().scene;
  const int w = camera.width, h = camera.height, tile_w = 16, tile_h = 4;
  const Eigen::Matrix3f rot = world_from_camera.linear().cast<float>();
  const Eigen::Vector3f org = world_from_camera.translation().cast<float>();
  // Camera-frame ray coordinates per column and row (z = 1).
  std::vector<float> xs(camera.width), ys(camera.height);
  for (int x = 0; x < camera.width; ++x) xs[x] = float((x + 0.5 - camera.cx) / camera.fx);
  for (int y = 0; y < camera.height; ++y) ys[y] = float((y + 0.5 - camera.cy) / camera.fy);
  const int tiles_x = (w + tile_w - 1) / tile_w, tiles_y = (h + tile_h - 1) / tile_h;
  std::atomic<size_t> hits{0};
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y), [&](const tbb::blocked_range<int>& range) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRayHit16 packet;
    alignas(64) int valid[16];
    size_t local = 0;
    for (int t = range.begin(); t != range.end(); ++t) {
      const int tx0 = (t % tiles_x) * tile_w, ty0 = (t / tiles_x) * tile_h;
      for (int sub = 0; sub < tile_w / 4; ++sub) {
        const int sx = tx0 + sub * 4, sy = ty0;
        if (sx >= w || sy >= h) continue;
        for (int lane = 0; lane < 16; ++lane) {
          const int px = std::min(sx + lane % 4, w - 1), py = std::min(sy + lane / 4, h - 1);
          valid[lane] = (sx + lane % 4 < w && sy + lane / 4 < h) ? -1 : 0;
          const Eigen::Vector3f d = rot * Eigen::Vector3f(xs[px], ys[py], 1.0f);
          SetPacketRay(packet, lane, Ray{org, d, 0.0f, max_depth});
        }
        rtcIntersect16(valid, scene, &context, &packet);
        for (int lane = 0; lane < 16; ++lane) local += valid[lane] && packet.hit.geomID[lane] != RTC_INVALID_GEOMETRY_ID;
      }
    }
    hits += local;
  });
  return hits.load();
}

// FNV-1a over the bytes of every buffer of a view, folded into `hash`.
void HashView(const RenderedView& view, uint64_t* hash) {
  const auto add = [&](const void* data, size_t bytes) {
    const auto* b = static_cast<const uint8_t*>(data);
    for (size_t i = 0; i < bytes; ++i) *hash = (*hash ^ b[i]) * 1099511628211ull;
  };
  add(view.rgb.data.data(), view.rgb.data.size());
  add(view.depth.data.data(), view.depth.data.size() * sizeof(float));
  for (float n : view.normal.data) {  // Zeros of either sign alike (earlier versions left -0 on some misses).
    n += 0.0f;
    add(&n, sizeof(float));
  }
  add(view.primitive.data.data(), view.primitive.data.size() * sizeof(int32_t));
  add(view.voxel_key.data.data(), view.voxel_key.data.size() * sizeof(VoxelKey));
  add(&view.hit_pixels, sizeof(view.hit_pixels));
}

// CPU seconds of the whole process (all threads).
double CpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int Run(int argc, char** argv) {
  std::vector<size_t> targets;
  int rounds = 5, threads = 2, yaws = 12, width = 640, height = 480;
  bool checksum = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--faces" && has_value) targets.push_back(size_t(std::atoll(argv[++i])));
    else if (a == "--rounds" && has_value) rounds = std::max(1, std::atoi(argv[++i]));
    else if (a == "--threads" && has_value) threads = std::max(1, std::atoi(argv[++i]));
    else if (a == "--views-per-position" && has_value) yaws = std::max(1, std::atoi(argv[++i]));
    else if (a == "--size" && has_value && std::sscanf(argv[++i], "%dx%d", &width, &height) == 2) continue;
    else if (a == "--checksum") checksum = true;
    else {
      std::fprintf(stderr, "usage: render_bench [--faces N ...] [--rounds R] [--threads T] [--views-per-position K] [--size WxH] "
                           "[--checksum]\n");
      return 2;
    }
  }
  if (targets.empty()) targets = {10'000, 1'000'000};
  tbb::global_control threads_limit(tbb::global_control::max_allowed_parallelism, size_t(threads));

  const std::string path = std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply";
  Result<Scene> demo = LoadScene(path);
  if (!demo.ok()) {
    std::fprintf(stderr, "render_bench: %s\n", demo.status().message().c_str());
    return 1;
  }
  Result<VoxelMap> map = Voxelize(demo.value(), VoxelizeOptions{});
  if (!map.ok()) {
    std::fprintf(stderr, "render_bench: %s\n", map.status().message().c_str());
    return 1;
  }
  ViewsOptions vo;
  vo.width = width;
  vo.height = height;
  double z = 0;
  const std::vector<Eigen::Vector3d> all = PlaceViewpoints(map.value(), vo, &z);
  std::vector<Eigen::Vector3d> positions;
  const size_t stride = std::max<size_t>(1, all.size() / 4);
  for (size_t i = 0; i < all.size() && positions.size() < 4; i += stride) positions.push_back(all[i]);
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& p : positions)
    for (int k = 0; k < yaws; ++k) poses.push_back(WorldFromCameraYawPitch(p, k * 360.0 / yaws, 0.0));
  const PinholeCamera camera = vo.Camera();
  const RenderOptions ro = vo.Render(0.05);
  const double rays_per_round = double(poses.size()) * camera.width * camera.height;
  std::printf("render_bench: %dx%d, hfov %.0f deg, %zu poses (%zu viewpoints x %d yaws), %d threads, %d rounds\n",
              camera.width, camera.height, camera.HorizontalFovDeg(), poses.size(), positions.size(), yaws, threads,
              rounds);

  for (size_t target : targets) {
    Scene scene;
    scene.mesh = Subdivide(demo->mesh, target);
    const auto tb = Clock::now();
    Result<ViewRenderer> renderer = ViewRenderer::Create(scene);
    if (!renderer.ok()) {
      std::fprintf(stderr, "render_bench: %s\n", renderer.status().message().c_str());
      return 1;
    }
    const double build_s = std::chrono::duration<double>(Clock::now() - tb).count();
    RenderedView view;
    std::vector<double> bare_rates, full_rates, bare_cpu_rates, full_cpu_rates;
    size_t bare_hits = 0, full_hits = 0;
    for (int r = 0; r < rounds; ++r) {
      // Bare and full alternate pose by pose, so that both see the same machine load.
      double bare_s = 0, full_s = 0, bare_cpu = 0, full_cpu = 0;
      bare_hits = full_hits = 0;
      for (const auto& pose : poses) {
        const double c0 = CpuSeconds();
        auto t0 = Clock::now();
        bare_hits += BareRender(renderer->raycaster(), camera, pose, float(ro.max_depth_m));
        const auto t1 = Clock::now();
        const double c1 = CpuSeconds();
        Status st = renderer->Render(camera, pose, ro, &view);
        const auto t2 = Clock::now();
        const double c2 = CpuSeconds();
        bare_cpu += c1 - c0;
        full_cpu += c2 - c1;
        if (!st.ok()) {
          std::fprintf(stderr, "render_bench: %s\n", st.message().c_str());
          return 1;
        }
        full_hits += view.hit_pixels;
        bare_s += std::chrono::duration<double>(t1 - t0).count();
        full_s += std::chrono::duration<double>(t2 - t1).count();
      }
      bare_rates.push_back(rays_per_round / bare_s);
      full_rates.push_back(rays_per_round / full_s);
      bare_cpu_rates.push_back(rays_per_round / bare_cpu);
      full_cpu_rates.push_back(rays_per_round / full_cpu);
    }
    const double bare_best = *std::max_element(bare_rates.begin(), bare_rates.end());
    const double full_best = *std::max_element(full_rates.begin(), full_rates.end());
    std::printf("%9zu triangles (build %.2f s): bare rtcIntersect16 %6.1f M rays/s (median %6.1f), full render %6.1f M rays/s "
                "(median %6.1f): full/bare %.0f%% (median %.0f%%); hits %zu / %zu%s\n",
                scene.mesh.faces.size(), build_s, bare_best / 1e6, Median(bare_rates) / 1e6, full_best / 1e6,
                Median(full_rates) / 1e6, 100.0 * full_best / bare_best, 100.0 * Median(full_rates) / Median(bare_rates),
                full_hits, bare_hits, full_hits == bare_hits ? "" : "  (MISMATCH)");
    if (threads == 1)  // No TBB workers: process CPU time is the render's own, whatever else the machine runs.
      std::printf("%9zu triangles: per CPU second: bare %6.1f M rays, full %6.1f M rays: full/bare %.0f%% (median of "
                  "rounds)\n",
                  scene.mesh.faces.size(), Median(bare_cpu_rates) / 1e6, Median(full_cpu_rates) / 1e6,
                  100.0 * Median(full_cpu_rates) / Median(bare_cpu_rates));
    if (checksum) {
      uint64_t hash = 14695981039346656037ull, pose_hash = hash;
      for (const auto& pose : poses) {
        const Eigen::Matrix4d m = pose.matrix();
        for (int k = 0; k < 16; ++k) {
          const auto* b = reinterpret_cast<const uint8_t*>(m.data() + k);
          for (size_t j = 0; j < sizeof(double); ++j) pose_hash = (pose_hash ^ b[j]) * 1099511628211ull;
        }
        if (Status st = renderer->Render(camera, pose, ro, &view); !st.ok()) {
          std::fprintf(stderr, "render_bench: %s\n", st.message().c_str());
          return 1;
        }
        HashView(view, &hash);
      }
      std::printf("%9zu triangles: checksum of all buffers of all %zu views %016llx (poses %016llx)\n",
                  scene.mesh.faces.size(), poses.size(), (unsigned long long)hash, (unsigned long long)pose_hash);
    }
  }
  return 0;
}

}  // namespace
}  // namespace semvox

int main(int argc, char** argv) { return semvox::Run(argc, argv); }
