// Clouds against meshes: the same generated apartment as a mesh and as a simulated fused
// cloud (`semvox generate --seed N --cloud`), rendered from the same poses; build and trace CPU seconds of
// each, and how far the cloud's views agree with the mesh's: the share of pixels that hit in both, the NYU40
// label of the hit primitive (face or point attribute "label") and the depth.
//
//   cloud_render_bench MESH.ply CLOUD.ply [--cell M ...] [--radius-factor F] [--squares] [--size WxH]
//
// One row per cloud setting (--cell 0 is one disc per point). Poses: the automatic viewpoints of the mesh's
// voxel map (render/views.h), 12 yaws each, 640 x 480, 90 degrees. CPU seconds are the process's (all
// threads), so they hold on a shared machine.
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "io/load_scene.h"
#include "mapping/voxelizer.h"
#include "render/view_renderer.h"
#include "render/views.h"

namespace semvox {
namespace {

double CpuNow() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

int Run(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: cloud_render_bench MESH.ply CLOUD.ply [--cell M ...] [--radius-factor F] [--squares] [--size WxH]\n");
    return 2;
  }
  std::vector<double> cells;
  double radius_factor = 1.0;
  bool squares = false;
  int width = 640, height = 480;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--cell" && i + 1 < argc) cells.push_back(std::atof(argv[++i]));
    else if (a == "--radius-factor" && i + 1 < argc) radius_factor = std::atof(argv[++i]);
    else if (a == "--squares") squares = true;
    else if (a == "--size" && i + 1 < argc && std::sscanf(argv[++i], "%dx%d", &width, &height) == 2) continue;
    else {
      std::fprintf(stderr, "cloud_render_bench: unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  if (cells.empty()) cells = {0.0, 0.05};
  LoadOptions lo;
  lo.canonical_frame = false;
  Result<Scene> mesh = LoadScene(argv[1], lo);
  Result<Scene> cloud = LoadScene(argv[2], lo);
  if (!mesh.ok() || !cloud.ok()) {
    std::fprintf(stderr, "cloud_render_bench: %s\n", (!mesh.ok() ? mesh.status() : cloud.status()).message().c_str());
    return 1;
  }
  Result<VoxelMap> map = Voxelize(mesh.value(), VoxelizeOptions{});
  if (!map.ok()) return 1;
  const std::vector<Eigen::Vector3d> positions = PlaceViewpoints(map.value(), ViewsOptions{}, nullptr);
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& p : positions)
    for (int k = 0; k < 12; ++k) poses.push_back(WorldFromCameraYawPitch(p, 30.0 * k, 0.0));
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(width, height, 90);
  const RenderOptions render{0.05, 50.0};
  const auto& face_label = mesh->mesh.face_attributes.at("label");
  const auto it = cloud->cloud.point_attributes.find("label");
  const std::vector<int32_t>* point_label = it == cloud->cloud.point_attributes.end() ? nullptr : &it->second;

  double t0 = CpuNow();
  Result<ViewRenderer> mesh_renderer = ViewRenderer::Create(mesh.value());
  const double mesh_build = CpuNow() - t0;
  if (!mesh_renderer.ok()) return 1;
  std::vector<RenderedView> reference(poses.size());
  t0 = CpuNow();
  for (size_t i = 0; i < poses.size(); ++i)
    if (!mesh_renderer->Render(camera, poses[i], render, &reference[i]).ok()) return 1;
  const double mesh_trace = CpuNow() - t0;
  std::printf("%zu poses, %dx%d; mesh %zu faces: build %.2f CPU s, trace %.3f CPU s per view\n", poses.size(), width, height,
              mesh->mesh.faces.size(), mesh_build, mesh_trace / double(poses.size()));
  std::printf("%-8s %-7s %9s %9s %11s %9s %12s %12s\n", "cell_m", "radius", "discs", "build_s", "trace_s/view", "vs_mesh",
              "both_hit", "label_agree");
  for (double cell : cells) {
    RaycasterOptions ro;
    ro.cloud_cell_m = cell;
    ro.point_radius_factor = radius_factor;
    ro.cloud_squares = squares;
    t0 = CpuNow();
    Result<ViewRenderer> r = ViewRenderer::Create(cloud.value(), ro);
    const double build = CpuNow() - t0;
    if (!r.ok()) return 1;
    RenderedView view;
    double trace = 0;
    size_t either = 0, both = 0, agree = 0, labelled = 0;
    double depth_err = 0;
    for (size_t i = 0; i < poses.size(); ++i) {
      t0 = CpuNow();
      if (!r->Render(camera, poses[i], render, &view).ok()) return 1;
      trace += CpuNow() - t0;
      const RenderedView& ref = reference[i];
      for (size_t p = 0; p < view.primitive.data.size(); ++p) {
        const int32_t a = ref.primitive.data[p], b = view.primitive.data[p];
        either += a >= 0 || b >= 0;
        if (a < 0 || b < 0) continue;
        ++both;
        depth_err += std::abs(double(ref.depth.data[p]) - double(view.depth.data[p]));
        if (point_label) {
          ++labelled;
          agree += face_label[size_t(a)] == (*point_label)[size_t(b)];
        }
      }
    }
    std::printf("%-8.3f %-7.2f %9zu %9.2f %11.4f %9.2f %11.4f %12.4f   (mean |depth diff| %.4f m)\n", cell, radius_factor,
                r->raycaster().point_radii().size(), build, trace / double(poses.size()), trace / mesh_trace,
                either ? double(both) / double(either) : 0.0, labelled ? double(agree) / double(labelled) : 0.0,
                both ? depth_err / double(both) : 0.0);
  }
  return 0;
}

}  // namespace
}  // namespace semvox

int main(int argc, char** argv) { return semvox::Run(argc, argv); }
