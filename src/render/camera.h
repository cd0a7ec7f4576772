// Pinhole cameras and poses for virtual views.
//
// Camera frame (as OpenCV and COLMAP): x right, y down, z forward (optical axis). Poses are stored as
// `world_from_camera` (maps camera coordinates to world coordinates); `camera_from_world` is its inverse.
// World frame: the input's own, metres, +Z up. A view at yaw 0 and pitch 0 looks along world +X; yaw turns
// counter-clockwise seen from above (towards +Y), pitch > 0 looks up.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

namespace semvox {

struct PinholeCamera {
  int width = 640;   // Pixels.
  int height = 480;  // Pixels.
  double fx = 0, fy = 0;  // Focal lengths, pixels.
  double cx = 0, cy = 0;  // Principal point, pixels (pixel (0,0)'s centre is at (0.5, 0.5)).

  // Square pixels, principal point at the image centre, horizontal field of view in degrees (0, 180).
  static PinholeCamera FromHorizontalFov(int width, int height, double horizontal_fov_deg);
  double HorizontalFovDeg() const;
  double VerticalFovDeg() const;
  // Direction in the camera frame through the centre of pixel (x, y), with z = 1, so that the ray
  // parameter of a hit is its depth along the optical axis.
  Eigen::Vector3d PixelRay(int x, int y) const { return {(x + 0.5 - cx) / fx, (y + 0.5 - cy) / fy, 1.0}; }
  bool Check(std::string* error) const;
};

// world_from_camera of a camera at `position` turned by yaw about world +Z and pitched up by pitch.
Eigen::Isometry3d WorldFromCameraYawPitch(const Eigen::Vector3d& position, double yaw_deg, double pitch_deg);

}  // namespace semvox
