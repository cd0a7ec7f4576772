// `semvox render`: virtual views of a scanned scene from given poses (the render stage of `semvox run` is
// pipeline/views_stage.h).
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "apps/commands.h"
#include "core/file_util.h"
#include "core/log.h"
#include "io/image_io.h"
#include "render/view_renderer.h"
#include "render/views.h"

namespace semvox {
namespace fs = std::filesystem;

namespace {
using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }

// 16-bit PNG depth in millimetres (0 = empty), as depth cameras write it; deeper than 65.535 m saturates.
ImageU16 DepthMillimetres(const RenderedView& v) {
  ImageU16 out(v.depth.width, v.depth.height, 1);
  for (size_t i = 0; i < v.depth.data.size(); ++i)
    out.data[i] = uint16_t(std::min(65535.0, std::round(double(v.depth.data[i]) * 1000.0)));
  return out;
}

// Normals as colours: (n + 1) / 2 * 255 per axis, black where empty.
ImageRgb8 NormalColours(const RenderedView& v) {
  ImageRgb8 out(v.normal.width, v.normal.height, 3);
  for (size_t i = 0; i < v.primitive.data.size(); ++i) {
    if (v.primitive.data[i] < 0) continue;
    for (int c = 0; c < 3; ++c) out.data[3 * i + c] = uint8_t(std::lround((v.normal.data[3 * i + c] + 1.0f) * 127.5f));
  }
  return out;
}

// Each voxel key in its own colour (a hash of the key), black where empty: shows the voxel grid as the
// views see it.
ImageRgb8 KeyColours(const RenderedView& v) {
  ImageRgb8 out(v.voxel_key.width, v.voxel_key.height, 3);
  for (size_t i = 0; i < v.primitive.data.size(); ++i) {
    if (v.primitive.data[i] < 0) continue;
    uint64_t h = v.voxel_key.data[i].Pack() * 0x9E3779B97F4A7C15ull;
    h ^= h >> 29;
    for (int c = 0; c < 3; ++c) out.data[3 * i + c] = uint8_t(64 + ((h >> (8 * c)) & 0xFF) % 192);
  }
  return out;
}

// "x,y,z,yaw_deg[,pitch_deg]"
Status ParsePose(const std::string& text, Eigen::Vector3d* position, double* yaw_deg, double* pitch_deg) {
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(v))
      return Status::InvalidInput("--pose '" + text + "': '" + item + "' is not a number (hint: --pose x,y,z,yaw_deg[,pitch_deg])");
    values.push_back(v);
  }
  if (values.size() != 4 && values.size() != 5)
    return Status::InvalidInput("--pose '" + text + "': expected 4 or 5 numbers, got " + std::to_string(values.size()) +
                                " (hint: --pose x,y,z,yaw_deg[,pitch_deg])");
  *position = Eigen::Vector3d(values[0], values[1], values[2]);
  *yaw_deg = values[3];
  *pitch_deg = values.size() == 5 ? values[4] : 0.0;
  if (std::abs(*pitch_deg) > 89) return Status::InvalidInput("--pose '" + text + "': pitch must lie in [-89, 89] degrees");
  return Status::Ok();
}

}  // namespace

Status RunRender(const RenderArgs& args) {
  PipelineConfig config;
  if (!args.config_path.empty()) SEMVOX_RETURN_IF_ERROR(LoadConfigFile(args.config_path, &config));
  if (!args.up.empty() && !ParseUpAxis(args.up, &config.load.up))
    return Status::InvalidInput("--up " + args.up + ": not an axis (hint: auto, z, y, -y, x, -x, -z)");
  if (args.scale > 0) config.load.scale = args.scale;
  if (args.horizontal_fov_deg > 0) config.render.horizontal_fov_deg = args.horizontal_fov_deg;
  if (args.width > 0) config.render.width = args.width;
  if (args.height > 0) config.render.height = args.height;
  if (args.voxel_size_m > 0) config.voxelize.voxel_size_m = args.voxel_size_m;
  SEMVOX_RETURN_IF_ERROR(CheckConfig(config));
  if (args.poses.empty()) return Status::InvalidInput("no --pose given (hint: --pose x,y,z,yaw_deg[,pitch_deg])");
  struct Pose {
    Eigen::Vector3d p;
    double yaw, pitch;
  };
  std::vector<Pose> poses(args.poses.size());
  for (size_t i = 0; i < poses.size(); ++i)
    SEMVOX_RETURN_IF_ERROR(ParsePose(args.poses[i], &poses[i].p, &poses[i].yaw, &poses[i].pitch));
  SEMVOX_RETURN_IF_ERROR(EnsureWritableDirectory(args.outdir));

  Result<Scene> scene = LoadScene(args.input, config.load);
  if (!scene.ok()) return scene.status();
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene.value(), config.render.Raycaster());
  if (!renderer.ok()) return renderer.status();
  const ViewsOptions& vo = config.render;
  ViewSet set;
  set.camera = vo.Camera();
  set.voxel_size_m = config.voxelize.voxel_size_m;
  RenderedView view;
  for (size_t i = 0; i < poses.size(); ++i) {
    ViewRecord r;
    r.id = int(i);
    r.position = int(i);
    r.yaw_deg = poses[i].yaw;
    r.pitch_deg = poses[i].pitch;
    r.world_from_camera = WorldFromCameraYawPitch(poses[i].p, r.yaw_deg, r.pitch_deg);
    const auto t0 = Clock::now();
    SEMVOX_RETURN_IF_ERROR(renderer->Render(set.camera, r.world_from_camera, vo.Render(set.voxel_size_m), &view));
    const double seconds = Seconds(t0);
    MeasureView(view, vo, &r);
    char prefix[32];
    std::snprintf(prefix, sizeof(prefix), "view_%02zu_", i);
    const fs::path base = fs::path(args.outdir) / prefix;
    SEMVOX_RETURN_IF_ERROR(WriteImage(base.string() + "rgb.png", view.rgb));
    SEMVOX_RETURN_IF_ERROR(WriteImage(base.string() + "depth.png", DepthMillimetres(view)));
    SEMVOX_RETURN_IF_ERROR(WriteImage(base.string() + "normal.png", NormalColours(view)));
    SEMVOX_RETURN_IF_ERROR(WriteImage(base.string() + "keys.png", KeyColours(view)));
    SEMVOX_INFO(prefix << "*.png: " << view.hit_pixels << " of " << view.depth.data.size() << " pixels hit, median depth "
                       << r.median_depth_m << " m, colour spread " << r.color_stddev << ", "
                       << (r.kept() ? "would be kept" : std::string("would be dropped: ") + ViewDropName(r.drop))
                       << " (" << 1000.0 * seconds << " ms)");
    set.positions.push_back(poses[i].p);
    set.views.push_back(r);
  }
  SEMVOX_RETURN_IF_ERROR(WriteFileAtomic((fs::path(args.outdir) / "views.json").string(), ViewsToJson(set, vo, false)));
  SEMVOX_INFO("outputs in " << args.outdir << " (view_NN_{rgb,depth,normal,keys}.png: depth in mm, 0 = empty; views.json)");
  return Status::Ok();
}

}  // namespace semvox
