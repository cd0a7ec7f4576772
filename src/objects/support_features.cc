#include "objects/support_features.h"

#include <tbb/parallel_for.h>

#include <Eigen/Core>
#include <array>
#include <cmath>

namespace semvox {

bool SupportFeatureOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (entropy_window_px < 3 || entropy_window_px > 31 || entropy_window_px % 2 == 0)
    return fail("entropy_window_px = " + std::to_string(entropy_window_px) + ". Violated constraint: odd, 3 <= entropy_window_px <= 31");
  if (!(depth_bin_m > 0)) return fail("depth_bin_m = " + std::to_string(depth_bin_m) + ". Violated constraint: depth_bin_m > 0");
  if (!(min_depth_fraction > 0 && min_depth_fraction <= 1))
    return fail("min_depth_fraction = " + std::to_string(min_depth_fraction) + ". Violated constraint: 0 < min_depth_fraction <= 1");
  return true;
}

ImageF32 LocalEntropy(const Image<uint8_t>& channel, int window) {
  const int w = channel.width, h = channel.height, r = window / 2;
  ImageF32 out(w, h, 1, 0.f);
  const int max_count = window * window;
  // c log2 c for every count a window can hold.
  std::vector<double> clogc(static_cast<size_t>(max_count) + 1, 0.0);
  // log2 n for every pixel count a window can hold (a table: the count changes only near the border).
  std::vector<double> log2n(static_cast<size_t>(max_count) + 1, 0.0);
  for (int c = 1; c <= max_count; ++c) clogc[size_t(c)] = c * std::log2(double(c)), log2n[size_t(c)] = std::log2(double(c));
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& range) {
    std::array<int, 256> hist;
    for (int y = range.begin(); y < range.end(); ++y) {
      const int y0 = std::max(0, y - r), y1 = std::min(h - 1, y + r);
      hist.fill(0);
      double s = 0;  // sum over bins of c log2 c
      int n = 0;
      auto add = [&](int x, int delta) {
        for (int yy = y0; yy <= y1; ++yy) {
          int& c = hist[channel.at(x, yy)];
          s -= clogc[size_t(c)];
          c += delta;
          s += clogc[size_t(c)];
        }
        n += delta * (y1 - y0 + 1);
      };
      for (int x = 0; x <= std::min(r, w - 1); ++x) add(x, +1);
      for (int x = 0; x < w; ++x) {
        // Eq. 1 with p = c / n: -sum p log2 p = log2 n - (1/n) sum c log2 c.
        out.at(x, y) = float(std::max(0.0, log2n[size_t(n)] - s / n));
        // Remove the leaving column before adding the entering one: a bin never holds more than window^2.
        if (x - r >= 0) add(x - r, -1);
        if (x + r + 1 < w) add(x + r + 1, +1);
      }
    }
  });
  return out;
}

Result<SupportFeatures> ComputeSupportFeatures(const RenderedView& view, const Superpixels& superpixels,
                                               const SupportFeatureOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("support features: " + error);
  const int w = view.rgb.width, h = view.rgb.height;
  if (view.rgb.channels != 3 || w == 0 || view.depth.width != w || view.depth.height != h || view.normal.width != w ||
      superpixels.label.width != w || superpixels.label.height != h)
    return Status::InvalidInput("support features: view images and superpixels must have one size");
  // Channels for the entropy maps: R, G, B and quantised depth.
  std::array<Image<uint8_t>, 4> channels;
  for (auto& c : channels) c = Image<uint8_t>(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) channels[size_t(c)].at(x, y) = view.rgb.at(x, y, c);
      const float d = view.depth.at(x, y);
      channels[3].at(x, y) = d > 0 ? uint8_t(1 + (int64_t(std::floor(d / options.depth_bin_m)) % 255)) : uint8_t(0);
    }
  std::array<ImageF32, 4> entropy;
  for (int c = 0; c < 4; ++c) entropy[size_t(c)] = LocalEntropy(channels[size_t(c)], options.entropy_window_px);

  const int count = superpixels.count;
  std::vector<Eigen::Vector3d> point_sum(size_t(count), Eigen::Vector3d::Zero()), normal_sum(size_t(count), Eigen::Vector3d::Zero());
  std::vector<std::array<double, 4>> entropy_sum(size_t(count), {0, 0, 0, 0});
  std::vector<int> hits(size_t(count), 0);
  SupportFeatures out;
  out.count = count;
  out.pixel_count.assign(size_t(count), 0);
  const Eigen::Matrix3d R = view.world_from_camera.linear();
  const Eigen::Vector3d t = view.world_from_camera.translation();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int s = superpixels.label.at(x, y);
      if (s < 0 || s >= count) return Status::InvalidInput("support features: superpixel label out of range");
      ++out.pixel_count[size_t(s)];
      for (int c = 0; c < 4; ++c) entropy_sum[size_t(s)][size_t(c)] += entropy[size_t(c)].at(x, y);
      const float d = view.depth.at(x, y);
      if (!(d > 0)) continue;
      ++hits[size_t(s)];
      point_sum[size_t(s)] += t + R * (view.camera.PixelRay(x, y) * double(d));
      normal_sum[size_t(s)] += Eigen::Vector3d(view.normal.at(x, y, 0), view.normal.at(x, y, 1), view.normal.at(x, y, 2));
    }
  // The camera's yaw frame: forward = optical axis projected on the floor, right = forward x up.
  Eigen::Vector3d forward = R.col(2);
  forward.z() = 0;
  if (forward.norm() < 1e-6) forward = R.col(1), forward.z() = 0;  // Looking straight down: image "down".
  forward.normalize();
  const Eigen::Vector3d right(forward.y(), -forward.x(), 0.0);
  out.rows.assign(size_t(count) * kSupportFeatureDims, 0.f);
  out.has_depth.assign(size_t(count), 0);
  for (int s = 0; s < count; ++s) {
    float* row = &out.rows[size_t(s) * kSupportFeatureDims];
    const int n = out.pixel_count[size_t(s)];
    if (n > 0)
      for (int c = 0; c < 4; ++c) row[kSupportEntropyR + c] = float(entropy_sum[size_t(s)][size_t(c)] / n);
    if (n == 0 || hits[size_t(s)] < options.min_depth_fraction * n) continue;
    out.has_depth[size_t(s)] = 1;
    row[kSupportHeight] = float(point_sum[size_t(s)].z() / hits[size_t(s)]);
    const Eigen::Vector3d normal = normal_sum[size_t(s)].norm() > 1e-9 ? normal_sum[size_t(s)].normalized() : Eigen::Vector3d::Zero();
    row[kSupportNormalRight] = float(normal.dot(right));
    row[kSupportNormalForward] = float(normal.dot(forward));
    row[kSupportNormalUp] = float(normal.z());
  }
  return out;
}

}  // namespace semvox
