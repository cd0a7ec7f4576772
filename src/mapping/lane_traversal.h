// Rays of TraverseGrid<true> (mapping/ray_traversal.h) stepped several at a time (internal to
// semvox_mapping: frame_integrator.cc marks every cell a ray enters free, voxelizer.cc's free-space cast
// stops at the first occupied one). Each ray is set up and stepped with exactly TraverseGrid<true>'s
// arithmetic, so the cells visited are the same in every instruction set.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>

#include "mapping/ray_traversal.h"

namespace semvox {

struct LaneRay {
  int64_t idx = 0, end_idx = 0, budget = -1;
  int64_t step_idx[3] = {0, 0, 0};
  double t_max[3] = {0, 0, 0}, t_delta[3] = {0, 0, 0};
  double length = 0;
};

// The ray from `origin` (cell `cur`) to `end` (cell `ke`, a different one), cells relative to the grid whose
// key origin is `grid_origin_key`; the lane steps from the origin's cell, which the caller visits.
inline void SetUpLaneRay(const Eigen::Vector3f& origin, const Eigen::Vector3f& end, const int64_t cur[3], const int64_t ke[3],
                         double resolution, const int grid_origin_key[3], const int64_t stride[3], LaneRay* ray) {
  ray->idx = cur[2] * stride[2] + cur[1] * stride[1] + cur[0];
  float direction[3] = {end[0] - origin[0], end[1] - origin[1], end[2] - origin[2]};
  const float norm_sq = direction[0] * direction[0] + direction[1] * direction[1] + direction[2] * direction[2];
  const float length = float(std::sqrt(double(norm_sq)));
  for (float& d : direction) d /= length;
  ray->length = length;
  for (int i = 0; i < 3; ++i) {
    const int step = direction[i] > 0.0f ? 1 : (direction[i] < 0.0f ? -1 : 0);
    ray->step_idx[i] = step * stride[i];
    if (step != 0) {
      double border = (double(cur[i] + grid_origin_key[i] - kKeyOffset) + 0.5) * resolution;
      border += float(step * resolution * 0.5);
      ray->t_max[i] = (border - origin[i]) / direction[i];
      ray->t_delta[i] = resolution / std::fabs(direction[i]);
    } else {
      ray->t_max[i] = std::numeric_limits<double>::max();
      ray->t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  ray->end_idx = ke[2] * stride[2] + ke[1] * stride[1] + ke[0];
  ray->budget = std::abs(ke[0] - cur[0]) + std::abs(ke[1] - cur[1]) + std::abs(ke[2] - cur[2]) + kInsideMargin;
}

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // Vectors never cross a call here (all helpers are inlined).

template <int kLanes>
struct LaneVectors {
  typedef double D __attribute__((vector_size(8 * kLanes)));
  typedef int64_t L __attribute__((vector_size(8 * kLanes)));
};

// Steps kLanes rays at once (GCC vector extensions: one SIMD register per quantity with AVX2 and 4 lanes,
// SSE2 with 2), each exactly as TraverseGrid<true>'s loop: the axis with the smallest t_max (ties as
// OctoMap breaks them), stop on entering the end cell or when the smallest t_max passes the length, or when
// the step budget is spent. `visit(cell)` sees every other cell entered and returns false to end the ray
// there. A lane whose ray is done takes the next ray so that all lanes keep working. The t_max updates are
// additions only (no product to fuse), so the arithmetic is the same in every instruction set.
template <int kLanes, typename Visit>
inline __attribute__((always_inline)) void TraverseLanes(const LaneRay* rays, size_t count, uint8_t* cells, Visit&& visit) {
  using D = typename LaneVectors<kLanes>::D;
  using L = typename LaneVectors<kLanes>::L;
  D t0, t1, t2, d0, d1, d2, len;
  L idx, end, s0, s1, s2, budget, active;
  size_t next = 0;
  const auto load = [&](int lane) {
    // The next ray into `lane`, or an idle lane when none is left.
    if (next < count) {
      const LaneRay& r = rays[next++];
      t0[lane] = r.t_max[0], t1[lane] = r.t_max[1], t2[lane] = r.t_max[2];
      d0[lane] = r.t_delta[0], d1[lane] = r.t_delta[1], d2[lane] = r.t_delta[2];
      len[lane] = r.length;
      idx[lane] = r.idx, end[lane] = r.end_idx;
      s0[lane] = r.step_idx[0], s1[lane] = r.step_idx[1], s2[lane] = r.step_idx[2];
      budget[lane] = r.budget;
      active[lane] = -1;
    } else {
      t0[lane] = t1[lane] = t2[lane] = d0[lane] = d1[lane] = d2[lane] = len[lane] = 0;
      idx[lane] = end[lane] = s0[lane] = s1[lane] = s2[lane] = budget[lane] = 0;
      active[lane] = 0;
    }
  };
  for (int lane = 0; lane < kLanes; ++lane) load(lane);
  while (true) {
    budget -= 1;
    active &= budget >= 0;
    const L a01 = t0 < t1, a02 = t0 < t2, a12 = t1 < t2;
    const L m0 = a01 & a02, m1 = ~a01 & a12, m2 = ~(m0 | m1);
    idx += (m0 & s0) | (m1 & s1) | (m2 & s2);
    t0 = m0 ? t0 + d0 : t0;
    t1 = m1 ? t1 + d1 : t1;
    t2 = m2 ? t2 + d2 : t2;
    active &= idx != end;
    D mn = t1 < t0 ? t1 : t0;  // std::min(std::min(t0, t1), t2).
    mn = t2 < mn ? t2 : mn;
    active &= ~(mn > len);
    bool all = true;
    for (int lane = 0; lane < kLanes; ++lane) {
      if (active[lane] && !visit(cells + idx[lane])) active[lane] = 0;
      all &= active[lane] != 0;
    }
    if (all) continue;
    bool any = false;
    for (int lane = 0; lane < kLanes; ++lane) {
      if (!active[lane]) load(lane);
      any |= active[lane] != 0;
    }
    if (!any) return;
  }
}

#pragma GCC diagnostic pop

}  // namespace semvox
