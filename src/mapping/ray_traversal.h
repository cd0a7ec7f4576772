// Voxel traversal along a segment (Amanatides & Woo 1987), in OctoMap key space.
//
// TraverseGrid visits the same keys, in the same order, as octomap::OcTreeBaseImpl::computeRayKeys
// (OctoMap 1.9): the origin's key first, then every key the segment crosses, excluding the end point's
// key; it mirrors OctoMap's float/double arithmetic so the key sets are identical, which
// bench/voxelize_bench checks on every run.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <type_traits>

#include "core/voxel_key.h"

namespace semvox {

// The traversal over a dense grid whose first cell has key `grid_origin_key` and whose size is
// `dims`: visit(size_t index) receives the linear index (x fastest) of each cell, origin cell first, end
// cell excluded, and stops at the grid's boundary. A visitor taking (size_t index, double t) also receives
// the distance along the segment from `origin` at which the traversal enters the cell (0 for the origin's). Cheap per step (the index is carried along). Returns
// false when the origin is outside the grid.
//
// kInside = true is the caller's promise that both end cells lie inside the grid with a margin of
// kInsideMargin cells: the boundary test is then replaced by a step budget (Manhattan distance in cells
// plus kInsideMargin, more than OctoMap's distance test ever lets the ray overshoot), which makes each
// step cheaper.
inline constexpr int kInsideMargin = 4;

template <bool kInside = false, typename Visit>
bool TraverseGrid(const Eigen::Vector3f& origin, const Eigen::Vector3f& end, double resolution,
                  const int grid_origin_key[3], const int dims[3], Visit&& visit) {
  const double inv = 1.0 / resolution;
  int64_t cur[3], ke[3];
  for (int i = 0; i < 3; ++i) {
    cur[i] = int64_t(std::floor(origin[i] * inv)) + kKeyOffset - grid_origin_key[i];
    ke[i] = int64_t(std::floor(end[i] * inv)) + kKeyOffset - grid_origin_key[i];
    if (cur[i] < 0 || cur[i] >= dims[i]) return false;
  }
  if (cur[0] == ke[0] && cur[1] == ke[1] && cur[2] == ke[2]) return true;
  const int64_t stride[3] = {1, dims[0], int64_t(dims[0]) * dims[1]};
  size_t idx = size_t(cur[2] * stride[2] + cur[1] * stride[1] + cur[0]);
  auto call = [&visit](size_t i, double t) {
    if constexpr (std::is_invocable_v<Visit, size_t, double>) return visit(i, t);
    else return visit(i);
  };
  if (!call(idx, 0.0)) return true;
  float direction[3] = {end[0] - origin[0], end[1] - origin[1], end[2] - origin[2]};
  const float norm_sq = direction[0] * direction[0] + direction[1] * direction[1] + direction[2] * direction[2];
  const float length = float(std::sqrt(double(norm_sq)));
  for (float& d : direction) d /= length;
  int step[3];
  int64_t step_idx[3];
  double t_max[3], t_delta[3];
  for (int i = 0; i < 3; ++i) {
    step[i] = direction[i] > 0.0f ? 1 : (direction[i] < 0.0f ? -1 : 0);
    step_idx[i] = step[i] * stride[i];
    if (step[i] != 0) {
      double border = (double(cur[i] + grid_origin_key[i] - kKeyOffset) + 0.5) * resolution;
      border += float(step[i] * resolution * 0.5);
      t_max[i] = (border - origin[i]) / direction[i];
      t_delta[i] = resolution / std::fabs(direction[i]);
    } else {
      t_max[i] = std::numeric_limits<double>::max();
      t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  if constexpr (kInside) {
    const size_t end_idx = size_t(ke[2] * stride[2] + ke[1] * stride[1] + ke[0]);
    int64_t budget = std::abs(ke[0] - cur[0]) + std::abs(ke[1] - cur[1]) + std::abs(ke[2] - cur[2]) + kInsideMargin;
    while (--budget >= 0) {
      const int a01 = t_max[0] < t_max[1], a02 = t_max[0] < t_max[2], a12 = t_max[1] < t_max[2];
      const int d = 2 - 2 * (a01 & a02) - ((1 - a01) & a12);
      idx += step_idx[d];
      const double t_cross = t_max[d];
      t_max[d] += t_delta[d];
      if (idx == end_idx) break;
      if (std::min(std::min(t_max[0], t_max[1]), t_max[2]) > length) break;
      if (!call(idx, t_cross)) break;
    }
    return true;
  }
  while (true) {
    // The axis with the smallest t_max, chosen without branches: the choice is close to random from step
    // to step, and mispredicted branches cost more than the whole rest of the step.
    const int a01 = t_max[0] < t_max[1], a02 = t_max[0] < t_max[2], a12 = t_max[1] < t_max[2];
    const int d = 2 - 2 * (a01 & a02) - ((1 - a01) & a12);
    cur[d] += step[d];
    if (cur[d] < 0 || cur[d] >= dims[d]) break;
    idx += step_idx[d];
    const double t_cross = t_max[d];
    t_max[d] += t_delta[d];
    if (cur[0] == ke[0] && cur[1] == ke[1] && cur[2] == ke[2]) break;
    if (std::min(std::min(t_max[0], t_max[1]), t_max[2]) > length) break;
    if (!call(idx, t_cross)) break;
  }
  return true;
}

}  // namespace semvox
