// Hand-built rendered views for the perception tests: no renderer, every pixel set analytically.
#pragma once

#include <functional>

#include "render/camera.h"
#include "render/view_renderer.h"

namespace semvox::testing {

// What one pixel sees: depth along the optical axis (0 = nothing), world normal, colour.
struct PixelSample {
  float depth = 0;
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
  Rgb8 color{0, 0, 0};
};

inline RenderedView MakeView(int width, int height, const Eigen::Isometry3d& world_from_camera,
                             const std::function<PixelSample(int x, int y)>& sample) {
  RenderedView v;
  v.camera = PinholeCamera::FromHorizontalFov(width, height, 90);
  v.world_from_camera = world_from_camera;
  v.rgb = ImageRgb8(width, height, 3);
  v.depth = ImageF32(width, height, 1);
  v.normal = ImageF32(width, height, 3);
  v.primitive = Image<int32_t>(width, height, 1, -1);
  v.voxel_key = Image<VoxelKey>(width, height, 1);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const PixelSample s = sample(x, y);
      v.rgb.at(x, y, 0) = s.color.r;
      v.rgb.at(x, y, 1) = s.color.g;
      v.rgb.at(x, y, 2) = s.color.b;
      v.depth.at(x, y) = s.depth;
      for (int c = 0; c < 3; ++c) v.normal.at(x, y, c) = s.normal[c];
      if (s.depth > 0) {
        v.primitive.at(x, y) = 0;
        ++v.hit_pixels;
      }
    }
  return v;
}

}  // namespace semvox::testing
