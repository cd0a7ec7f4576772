#include "rooms/floor_plan.h"

#include "io/image_io.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace semvox {
namespace {

// Deepest lintel: the thickest wall a door goes through, metres.
constexpr double kMaxLintelDepthM = 0.5;

std::string Violated(const char* field, double value, const std::string& constraint) {
  std::ostringstream os;
  os << field << " = " << value << ". Violated constraint: " << constraint;
  return os.str();
}

// Ceiling steps: the free cells split into ceiling zones, flooding between 4-neighbours whose ceiling
// heights differ by less than ceiling_step_m (so a gentle slope stays one zone). Where two zones of at
// least ceiling_zone_min_area_m2 meet, the cells along the step separate rooms like a door (a lamp or a
// lintel makes a small zone and is ignored).
void MarkCeilingSteps(const FloorPlanOptions& options, FloorPlan* plan) {
  const int W = plan->width(), H = plan->height();
  const float step = float(options.ceiling_step_m);
  auto known = [&](int x, int y) {
    return plan->at(x, y) == FloorCell::kFree && plan->ceiling_height_m.at(x, y) > 0;
  };
  std::vector<int> zone(size_t(W) * H, -1), area;
  std::vector<int> stack;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      if (!known(x, y) || zone[size_t(y) * W + x] >= 0) continue;
      const int z = int(area.size());
      area.push_back(0);
      stack.assign(1, y * W + x);
      zone[size_t(y) * W + x] = z;
      while (!stack.empty()) {
        const int p = stack.back();
        stack.pop_back();
        ++area[z];
        const int px = p % W, py = p / W;
        const float h = plan->ceiling_height_m.at(px, py);
        const int nx[4] = {px + 1, px - 1, px, px}, ny[4] = {py, py, py + 1, py - 1};
        for (int k = 0; k < 4; ++k) {
          if (nx[k] < 0 || ny[k] < 0 || nx[k] >= W || ny[k] >= H || !known(nx[k], ny[k])) continue;
          int& zq = zone[size_t(ny[k]) * W + nx[k]];
          if (zq >= 0 || std::fabs(plan->ceiling_height_m.at(nx[k], ny[k]) - h) >= step) continue;
          zq = z;
          stack.push_back(ny[k] * W + nx[k]);
        }
      }
    }
  const int min_cells = int(options.ceiling_zone_min_area_m2 / (plan->resolution_m * plan->resolution_m));
  std::vector<int> steps;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int z = zone[size_t(y) * W + x];
      if (z < 0 || area[z] < min_cells) continue;
      // The cell on the higher side of a step between two big zones.
      const int nx[4] = {x + 1, x - 1, x, x}, ny[4] = {y, y, y + 1, y - 1};
      for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || ny[k] < 0 || nx[k] >= W || ny[k] >= H) continue;
        const int zq = zone[size_t(ny[k]) * W + nx[k]];
        if (zq >= 0 && zq != z && area[zq] >= min_cells &&
            plan->ceiling_height_m.at(x, y) > plan->ceiling_height_m.at(nx[k], ny[k])) {
          steps.push_back(y * W + x);
          break;
        }
      }
    }
  for (int p : steps) plan->cells.at(p % W, p / W) = uint8_t(FloorCell::kDoor);
  plan->ceiling_step_cells = steps.size();
}

}  // namespace

size_t FloorPlan::Count(FloorCell kind) const {
  return size_t(std::count(cells.data.begin(), cells.data.end(), uint8_t(kind)));
}

bool FloorPlanOptions::Check(std::string* error) const {
  if (!CheckOptions(*this, Options(), error)) return false;
  if (!(door_max_width_m >= door_min_width_m))
    return *error = Violated("door_max_width_m", door_max_width_m, "door_max_width_m >= door_min_width_m"), false;
  return true;
}

FloorPlan FloorPlanFromVoxels(const VoxelGrid& grid, double floor_z, double ceiling_z, const OccupancyMap& occupancy,
                              const FloorPlanOptions& options) {
  const auto& dims = grid.dims();
  const int W = occupancy.image.width, H = occupancy.image.height;
  FloorPlan plan;
  plan.resolution_m = occupancy.resolution;
  plan.origin_x = occupancy.origin_x;
  plan.origin_y = occupancy.origin_y;
  plan.floor_z = floor_z;
  plan.cells = Image<uint8_t>(W, H, 1, uint8_t(FloorCell::kUnknown));
  plan.ceiling_height_m = ImageF32(W, H, 1, 0.f);
  if (W != dims[0] || H != dims[1] || W == 0 || H == 0) return plan;  // Not the grid's occupancy: nothing to do.

  const double res = grid.resolution();
  const double z0 = grid.MinCorner().z();
  // Voxel layer whose centre is at or above height h over the floor, clamped to the grid.
  auto layer_at = [&](double h) {
    return std::clamp(int(std::ceil((floor_z + h - z0) / res - 0.5)), 0, dims[2]);
  };
  const double top = ceiling_z > floor_z ? ceiling_z - floor_z : dims[2] * res;
  // Walls reach at least wall_min_height_m (or 80% of a low ceiling); lintels start at door_min_height_m.
  const int wall_lo = layer_at(std::min(options.wall_min_height_m, 0.8 * top));
  const int upper_hi = std::max(layer_at(top - options.lintel_ceiling_gap_m), wall_lo + 1);
  const int lintel_lo = layer_at(options.door_min_height_m);
  const int slab_lo = layer_at(0.0);

  // Free cells by the occupancy map; obstacles split into walls and clutter by their height.
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int iy = H - 1 - y;
      const uint8_t v = occupancy.image.at(x, y);
      FloorCell c = FloorCell::kUnknown;
      if (v == kPgmFree) {
        c = FloorCell::kFree;
      } else if (v == kPgmOccupied) {
        bool tall = false;
        for (int iz = wall_lo; iz < std::min(upper_hi, dims[2]) && !tall; ++iz)
          tall = grid.state(grid.Index(x, iy, iz)) == VoxelState::kOccupied;
        c = tall ? FloorCell::kWall : FloorCell::kClutter;
      }
      plan.cells.at(x, y) = uint8_t(c);
      // Ceiling height: the first occupied voxel above the door height with free space below it.
      if (c == FloorCell::kFree) {
        for (int iz = std::max(lintel_lo, slab_lo); iz < dims[2]; ++iz)
          if (grid.state(grid.Index(x, iy, iz)) == VoxelState::kOccupied) {
            plan.ceiling_height_m.at(x, y) = float(z0 + iz * res - floor_z);  // Underside of the voxel.
            break;
          }
      }
    }

  // Door openings: free cells with a lintel above (the first surface above the door height lies clearly
  // below the ceiling) in a gap no wider than a door (twice the distance to the nearest non-free cell).
  // A lintel is small: a connected patch of low ceiling larger than a door is a lowered ceiling instead.
  cv::Mat1b free_mask(H, W, uchar(0)), low(H, W, uchar(0));
  const double lintel_top_m = top - options.lintel_ceiling_gap_m;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      free_mask(y, x) = plan.cells.at(x, y) == uint8_t(FloorCell::kFree) ? 255 : 0;
      const double h = plan.ceiling_height_m.at(x, y);
      low(y, x) = free_mask(y, x) && h > 0 && h < lintel_top_m ? 255 : 0;
    }
  cv::Mat1f dist;
  cv::distanceTransform(free_mask, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  const float max_half_width_px = float(0.5 * options.door_max_width_m / res);
  cv::Mat1i low_labels;
  cv::Mat low_stats, low_centroids;
  const int n_low = cv::connectedComponentsWithStats(low, low_labels, low_stats, low_centroids, 8, CV_32S);
  const double max_lintel_cells = options.door_max_width_m * kMaxLintelDepthM / (res * res);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int c = low_labels(y, x);
      if (c > 0 && c < n_low && low_stats.at<int>(c, cv::CC_STAT_AREA) <= max_lintel_cells &&
          dist(y, x) <= max_half_width_px)
        plan.cells.at(x, y) = uint8_t(FloorCell::kDoor);
    }
  if (options.ceiling_step_m > 0) MarkCeilingSteps(options, &plan);
  return plan;
}

FloorPlan FloorPlanFromImage(const Image<uint8_t>& grey, double resolution_m, const FloorPlanOptions& options) {
  const int W = grey.width, H = grey.height;
  FloorPlan plan;
  plan.resolution_m = resolution_m;
  plan.cells = Image<uint8_t>(W, H, 1, uint8_t(FloorCell::kWall));
  plan.ceiling_height_m = ImageF32(W, H, 1, 0.f);
  if (W == 0 || H == 0) return plan;
  cv::Mat1b obstacle(H, W, uchar(0));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const bool free = grey.at(x, y) > options.free_threshold;
      plan.cells.at(x, y) = uint8_t(free ? FloorCell::kFree : FloorCell::kWall);
      obstacle(y, x) = free ? 0 : 255;
    }
  // Small obstacle islands (not touching the border, up to clutter_max_area_m2) are furniture.
  cv::Mat1i labels;
  cv::Mat stats, centroids;
  const int n = cv::connectedComponentsWithStats(obstacle, labels, stats, centroids, 8, CV_32S);
  const double max_px = options.clutter_max_area_m2 / (resolution_m * resolution_m);
  const double max_len_px = options.clutter_max_length_m / resolution_m;
  std::vector<uint8_t> is_clutter(n, 0);
  for (int i = 1; i < n; ++i) {
    const int x = stats.at<int>(i, cv::CC_STAT_LEFT), y = stats.at<int>(i, cv::CC_STAT_TOP);
    const int w = stats.at<int>(i, cv::CC_STAT_WIDTH), h = stats.at<int>(i, cv::CC_STAT_HEIGHT);
    const bool border = x == 0 || y == 0 || x + w == W || y + h == H;
    is_clutter[i] = !border && stats.at<int>(i, cv::CC_STAT_AREA) <= max_px && std::hypot(w, h) <= max_len_px;
  }
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if (is_clutter[labels(y, x)]) plan.cells.at(x, y) = uint8_t(FloorCell::kClutter);
  return plan;
}

Result<Image<uint8_t>> ReadGreyMap(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return Status::InvalidInput(FileError(path, "no such map image", "give a PNG or PGM map (0 occupied, 255 free)"));
  return ReadImageGrey8(path);
}

}  // namespace semvox
