// Voxelisation throughput: semvox's parallel frame integration against OctoMap's own insertPointCloud on
// the same rays, in the same run, checking that both give identical free / occupied voxels.
//
// The frame: a 640x480 pinhole camera (90 x 74 degrees) at scanner height inside the demo apartment, rays
// cast with Embree to the mesh (end points = exact surface hits), max range 5 m as in the reference figures.
//
//   build/bin/voxelize_bench [--mesh scenes/demo_apartment.ply] [--repeats 5] [--resolution 0.05] [--threads 2]
//
// --threads caps the threads semvox may use (OctoMap always runs on one); the default is all cores.
#include <octomap/OcTree.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "io/load_scene.h"
#include "mapping/frame_integrator.h"
#include "mapping/octomap_io.h"
#include "render/raycaster.h"

using namespace semvox;
using Clock = std::chrono::steady_clock;

static double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int main(int argc, char** argv) {
  std::string mesh_path = std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply";
  int repeats = 5, threads = 0;
  std::vector<double> resolutions = {0.05, 0.02};
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--mesh")) mesh_path = argv[i + 1];
    if (!std::strcmp(argv[i], "--repeats")) repeats = std::max(1, std::atoi(argv[i + 1]));
    if (!std::strcmp(argv[i], "--resolution")) resolutions = {std::atof(argv[i + 1])};
    if (!std::strcmp(argv[i], "--threads")) threads = std::max(1, std::atoi(argv[i + 1]));
  }
  std::unique_ptr<tbb::global_control> threads_limit;
  if (threads > 0)
    threads_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(threads));
  Result<Scene> scene = LoadScene(mesh_path);
  if (!scene.ok()) { std::fprintf(stderr, "%s\n", scene.status().message().c_str()); return 2; }
  Result<Raycaster> rc = Raycaster::FromScene(scene.value());
  if (!rc.ok()) { std::fprintf(stderr, "%s\n", rc.status().message().c_str()); return 1; }

  // One 640x480 frame from the living room towards the kitchen corner.
  const Eigen::Vector3f origin(1.2f, 1.3f, 1.5f);
  const int W = 640, H = 480;
  const double fx = 320.0, fy = 320.0, yaw = 0.9;
  std::vector<Ray> rays;
  rays.reserve(W * H);
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) {
      const double x = (u + 0.5 - W / 2.0) / fx, y = -(v + 0.5 - H / 2.0) / fy;  // camera: x right, y up, z forward
      const Eigen::Vector3d fwd(std::cos(yaw), std::sin(yaw), 0), right(std::sin(yaw), -std::cos(yaw), 0), up(0, 0, 1);
      Ray r;
      r.origin = origin;
      r.direction = (fwd + x * right + y * up).normalized().cast<float>();
      rays.push_back(r);
    }
  std::vector<RayHit> hits;
  rc->Intersect(rays, &hits);
  std::vector<Eigen::Vector3f> ends;
  octomap::Pointcloud cloud;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (!hits[i].hit()) continue;
    const Eigen::Vector3f p = rays[i].origin + hits[i].distance * rays[i].direction;
    ends.push_back(p);
    cloud.push_back(p.x(), p.y(), p.z());
  }
  const double max_range = 5.0;
  std::printf("frame: %zu rays with hits (of %d), max range %.1f m, mesh %s (%zu triangles)\n", ends.size(), W * H,
              max_range, std::filesystem::path(mesh_path).filename().c_str(), scene->mesh.faces.size());
  std::printf("%-6s %12s %12s %14s %14s %10s %10s %s\n", "res", "octomap_s", "semvox_s", "semvox_keys_s",
              "octomap_Mray/s", "speedup", "keys_x", "identical");
  const auto tmp = std::filesystem::temp_directory_path() / ("semvox_voxbench_" + std::to_string(::getpid()));
  std::filesystem::create_directories(tmp);
  bool all_identical = true;
  for (double res : resolutions) {
    std::vector<double> t_ref, t_ours, t_keys;
    bool identical = true;
    for (int rep = 0; rep < repeats; ++rep) {
      octomap::OcTree ref(res);
      auto t0 = Clock::now();
      ref.insertPointCloud(cloud, octomap::point3d(origin.x(), origin.y(), origin.z()), max_range, false, false);
      t_ref.push_back(std::chrono::duration<double>(Clock::now() - t0).count());

      OccupancyOctree ours(res);
      t0 = Clock::now();
      const FrameUpdate update = IntegrateFrame(origin, ends, res, max_range);
      const double keys_s = std::chrono::duration<double>(Clock::now() - t0).count();
      ours.Apply(update);
      t_ours.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
      t_keys.push_back(keys_s);

      if (rep == 0) {
        // Same free / occupied voxels: compare the full-depth leaves of both trees.
        const std::string b = (tmp / "ours.bt").string();
        if (!ours.WriteBinary(b).ok()) return 1;
        double r2;
        auto lb = ReadOctomapLeaves(b, &r2);
        std::vector<std::pair<VoxelKey, bool>> ref_leaves;
        for (auto it = ref.begin_leafs(), end = ref.end_leafs(); it != end; ++it) {
          const int span = 1 << (16 - int(it.getDepth()));
          const octomap::OcTreeKey k = it.getIndexKey();
          for (int dz = 0; dz < span; ++dz)
            for (int dy = 0; dy < span; ++dy)
              for (int dx = 0; dx < span; ++dx)
                ref_leaves.push_back({VoxelKey{uint16_t(k[0] + dx), uint16_t(k[1] + dy), uint16_t(k[2] + dz)},
                                      ref.isNodeOccupied(*it)});
        }
        std::sort(ref_leaves.begin(), ref_leaves.end());
        Result<std::vector<std::pair<VoxelKey, bool>>> la = ref_leaves;
        identical = la.ok() && lb.ok() && la.value() == lb.value();
        if (la.ok() && lb.ok())
          std::printf("  %.2f m: %zu free + %zu occupied keys; octomap leaves %zu, ours %zu\n", res, update.free.size(),
                      update.occupied.size(), la->size(), lb->size());
      }
    }
    all_identical &= identical;
    const double a = Median(t_ref), b = Median(t_ours), k = Median(t_keys);
    std::printf("%-6.2f %12.4f %12.4f %14.4f %14.3f %9.2fx %9.2fx %s\n", res, a, b, k, ends.size() / a / 1e6, a / b,
                a / k, identical ? "yes" : "NO");
  }
  std::filesystem::remove_all(tmp);
  std::printf("semvox_s = key computation (both cores) + OcTree update; keys_x = OctoMap time / key computation time\n");
  return all_identical ? 0 : 1;
}
