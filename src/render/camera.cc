#include "render/camera.h"

#include <cmath>
#include <numbers>
#include <sstream>

namespace semvox {
namespace {
constexpr double kDegToRad = std::numbers::pi / 180.0;
}

PinholeCamera PinholeCamera::FromHorizontalFov(int width, int height, double horizontal_fov_deg) {
  PinholeCamera c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = 0.5 * width / std::tan(0.5 * horizontal_fov_deg * kDegToRad);
  c.cx = 0.5 * width;
  c.cy = 0.5 * height;
  return c;
}

double PinholeCamera::HorizontalFovDeg() const { return 2.0 * std::atan(0.5 * width / fx) / kDegToRad; }
double PinholeCamera::VerticalFovDeg() const { return 2.0 * std::atan(0.5 * height / fy) / kDegToRad; }

bool PinholeCamera::Check(std::string* error) const {
  std::ostringstream os;
  if (width < 1 || width > 16384) os << "width = " << width << ". Violated constraint: 1 <= width <= 16384";
  else if (height < 1 || height > 16384) os << "height = " << height << ". Violated constraint: 1 <= height <= 16384";
  else if (!(fx > 0) || !(fy > 0) || !std::isfinite(fx) || !std::isfinite(fy))
    os << "fx = " << fx << ", fy = " << fy << ". Violated constraint: focal lengths > 0";
  else if (!std::isfinite(cx) || !std::isfinite(cy)) os << "principal point is not finite";
  if (os.str().empty()) return true;
  if (error) *error = os.str();
  return false;
}

Eigen::Isometry3d WorldFromCameraYawPitch(const Eigen::Vector3d& position, double yaw_deg, double pitch_deg) {
  const double yaw = yaw_deg * kDegToRad, pitch = pitch_deg * kDegToRad;
  // Camera axes expressed in the world frame.
  const Eigen::Vector3d forward(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
  const Eigen::Vector3d right(std::sin(yaw), -std::cos(yaw), 0.0);
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d r;
  r.col(0) = right;
  r.col(1) = down;
  r.col(2) = forward;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = r;
  t.translation() = position;
  return t;
}

}  // namespace semvox
