// Rendering one virtual view of a scene: colour, depth, normal, primitive id and, for every pixel, the
// OctoMap key of the voxel its hit point lies in.
//
//   Result<ViewRenderer> renderer = ViewRenderer::Create(scene);     // builds the Embree scene once
//   PinholeCamera camera = PinholeCamera::FromHorizontalFov(640, 480, 90);
//   RenderedView view;
//   renderer->Render(camera, WorldFromCameraYawPitch(p, 30, 0), RenderOptions{}, &view);
//   if (view.hit(x, y)) ... view.voxel_key.at(x, y) ...
//
// Pixels whose ray hits nothing (holes in the mesh, beyond max_depth_m) stay empty: black, depth 0,
// normal 0, primitive -1, key {0,0,0}. The image is traced in 16x4-pixel tiles spread over all cores (TBB),
// each tile as four 16-ray packets; every pixel is shaded by one pure function of its hit.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>

#include "core/geometry.h"
#include "core/image.h"
#include "core/status.h"
#include "core/voxel_key.h"
#include "render/camera.h"
#include "render/raycaster.h"

namespace semvox {

struct RenderOptions {
  // Resolution of the per-pixel voxel keys (the OctoMap resolution of the map), metres. [0.001, 10].
  double voxel_size_m = 0.05;
  // Hits deeper than this along the optical axis stay empty, metres. > 0.
  double max_depth_m = 100.0;

  bool Check(std::string* error) const;
};

struct RenderedView {
  PinholeCamera camera;
  Eigen::Isometry3d world_from_camera = Eigen::Isometry3d::Identity();
  ImageRgb8 rgb;              // 3 channels; texture, vertex or material colour (Mesh::ColorAt), cloud colour.
  ImageF32 depth;             // Depth along the optical axis (camera z), metres; 0 where empty.
  ImageF32 normal;            // 3 channels: unit surface normal in the world frame, facing the camera.
  Image<int32_t> primitive;   // Face (mesh) or point (cloud) index; -1 where empty.
  // OctoMap key (at voxel_size_m) of the voxel containing the hit point, with the voxeliser's convention for
  // points on a voxel boundary (within 1e-4 voxel below it counts as above), so that a pixel on a surface
  // gets exactly a voxel the voxeliser marked occupied for that surface.
  Image<VoxelKey> voxel_key;
  size_t hit_pixels = 0;

  bool hit(int x, int y) const { return primitive.at(x, y) >= 0; }
};

class ViewRenderer {
 public:
  // Builds the ray caster for the scene's mesh or cloud. `scene` must outlive the renderer (colours are
  // read from it while shading).
  static Result<ViewRenderer> Create(const Scene& scene, const RaycasterOptions& options = {});

  // Renders one view into `view`, reusing its buffers when the size is unchanged. Thread-safe (the
  // tiles already use every core, so there is little to gain from calling it concurrently).
  Status Render(const PinholeCamera& camera, const Eigen::Isometry3d& world_from_camera,
                const RenderOptions& options, RenderedView* view) const;

  const Raycaster& raycaster() const { return raycaster_; }
  const Scene& scene() const { return *scene_; }

 private:
  struct ShadeData;  // Per-face shading records (view_renderer.cc).
  ViewRenderer(const Scene* scene, Raycaster raycaster, std::shared_ptr<const ShadeData> shade)
      : scene_(scene), raycaster_(std::move(raycaster)), shade_(std::move(shade)) {}
  const Scene* scene_;
  Raycaster raycaster_;
  std::shared_ptr<const ShadeData> shade_;
};

// Box-filtered copy of `image` scaled to `width` pixels wide (height keeps the aspect ratio), for
// thumbnails. Returns `image` unchanged when it is not wider than `width`.
ImageRgb8 DownscaleImage(const ImageRgb8& image, int width);

}  // namespace semvox
