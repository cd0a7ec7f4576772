// The views stage: automatic viewpoints and virtual views of the whole apartment.
//
//   VoxelMap + Scene --RenderViews--> ViewSet (poses, intrinsics, kept / dropped, voxels seen)
//
// As in the room-labelling paper (Sec. III, "Overview"): viewpoints simulate a camera on a tripod turned
// about the upright axis, placed halfway between floor and ceiling; each viewpoint gets 36 views 10 degrees
// apart (yaw_step_deg), plus optional rings tilted up and down (tilted_ring_deg); a view is dropped when it is too close to a wall (median depth under
// min_median_depth_m) or its colour too homogeneous (colour spread under min_color_stddev). Positions
// spread over the whole free space: the mid-height layer of free voxels is cut into grid_spacing_m squares
// and each square that holds a free voxel at least wall_clearance_m from any non-free voxel gets one
// viewpoint, the clear voxel nearest the square's centre.
//
// Views are not kept in memory (a 640x480 view with all buffers is 9 MB, 160x120 a sixteenth); a ViewSink sees each one as it
// is rendered (thumbnails, per-view classifiers). The poses in views.json re-render any view exactly.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <string>
#include <vector>

#include "core/option_table.h"
#include "core/status.h"
#include "core/voxel_grid.h"
#include "mapping/voxelizer.h"
#include "render/camera.h"
#include "render/view_renderer.h"

namespace semvox {

struct ViewsOptions {
  // 4:3 as in the paper, at a quarter of its 640 x 480: the views are depth evidence for the Voxel-CRF (per-voxel
  // means of depth agreement and density, which do not depend on the resolution; 36 views of 90 degrees per
  // viewpoint see each direction nine times) and 160 x 120 keeps the labels of seven generated validation
  // runs within 0.3 points of 320 x 240 (better on average) at a third of the render stage (docs/speed.md).
  // The classification views have their own size (semantic.classify_width / classify_height, 320 x 240).
  int width = 160;
  int height = 120;
  double horizontal_fov_deg = 90.0;
  double height_fraction = 0.5;
  double grid_spacing_m = 1.5;        // 1.5 m keeps 96% coverage of the demo scene with half the views of 1 m.
  double wall_clearance_m = 0.4;
  double yaw_step_deg = 10.0;         // 36 views.
  double pitch_deg = 0.0;
  // The tilted rings are for a tripod with several cameras like the Matterport scanner of the paper's data;
  // without them the floor and ceiling near each viewpoint stay unseen. -89 <= pitch_deg +- tilted_ring_deg <= 89.
  double tilted_ring_deg = 0.0;
  double tilted_ring_yaw_step_deg = 30.0;
  double max_depth_m = 50.0;
  double min_median_depth_m = 0.8;    // Over hit pixels.
  double min_color_stddev = 6.0;      // RMS of the per-channel standard deviations over hit pixels.
  double min_hit_fraction = 0.25;
  int thumbnail_width = 160;
  double cloud_cell_m = 0.05;         // RaycasterOptions::cloud_cell_m.
  // RaycasterOptions::point_radius_factor. On a square grid of spacing s the mean distance to the 8 nearest
  // discs is 1.21 s and discs close the plane from 0.59 on; larger factors overlap more and cost more rays' tests.
  double cloud_radius_factor = 0.75;
  // RaycasterOptions::cloud_squares. On generated apartments squares of 0.7-0.8 x the spacing at 5 cm cells
  // trace in 1.2-1.4 x a mesh's time where single-point discs took 4.8 x, with labels agreeing with the mesh's
  // views as well or better (bench/cloud_render_bench.cc, docs/speed.md).
  bool cloud_squares = true;

  // The fields users set (section `render`): meaning, unit and range.
  static const OptionTable<ViewsOptions>& Options() {
    using O = ViewsOptions;
    static const OptionTable<O> table = {
        OptionNumber(&O::width, "width", 16, 8192, "pixels", "view width"),
        OptionNumber(&O::height, "height", 16, 8192, "pixels", "view height"),
        OptionNumber(&O::horizontal_fov_deg, "horizontal_fov_deg", 2, 170, "degrees", "horizontal field of view"),
        OptionNumber(&O::height_fraction, "height_fraction", 0.05, 0.95, "",
                     "camera height between floor (0) and ceiling (1)"),
        OptionNumber(&O::grid_spacing_m, "grid_spacing_m", 0.1, 100, "metres", "one viewpoint per square of this side"),
        OptionNumber(&O::wall_clearance_m, "wall_clearance_m", 0, 10, "metres",
                     "min distance from a viewpoint to a non-free voxel"),
        OptionNumber(&O::yaw_step_deg, "yaw_step_deg", 1, 360, "degrees",
                     "yaw between views of a viewpoint (divides 360)"),
        OptionNumber(&O::pitch_deg, "pitch_deg", -89, 89, "degrees", "camera pitch of the main ring (> 0 looks up)"),
        OptionNumber(&O::tilted_ring_deg, "tilted_ring_deg", 0, 89, "degrees",
                     "extra rings tilted down and up by this much (0: none)"),
        OptionNumber(&O::tilted_ring_yaw_step_deg, "tilted_ring_yaw_step_deg", 1, 360, "degrees",
                     "yaw between views of the tilted rings (divides 360)"),
        OptionNumber(&O::max_depth_m, "max_depth_m", 0.01, 1e6, "metres", "hits deeper than this stay empty"),
        OptionNumber(&O::min_median_depth_m, "min_median_depth_m", 0, 100, "metres",
                     "drop views with a smaller median depth (too close to a wall)"),
        OptionNumber(&O::min_color_stddev, "min_color_stddev", 0, 255, "0-255",
                     "drop views with a smaller colour spread (too homogeneous)"),
        OptionNumber(&O::min_hit_fraction, "min_hit_fraction", 0, 1, "", "drop views where fewer pixels hit the scene"),
        OptionNumber(&O::thumbnail_width, "thumbnail_width", 16, 8192, "pixels", "width of --save-views thumbnails"),
        OptionNumber(&O::cloud_cell_m, "cloud_cell_m", 0, 1, "metres",
                     "point clouds: points of each cube of this side are drawn as one disc at their centroid (0: one "
                     "disc per point)"),
        OptionNumber(&O::cloud_radius_factor, "cloud_radius_factor", 1e-3, 10, "",
                     "point clouds: disc radius as a multiple of the mean distance to the 8 nearest discs"),
        OptionSwitch(&O::cloud_squares, "cloud_squares",
                     "point clouds: draw each disc as the square around it (two triangles, about 3 x faster to trace "
                     "than a disc)"),
    };
    return table;
  }
  bool Check(std::string* error) const;
  PinholeCamera Camera() const { return PinholeCamera::FromHorizontalFov(width, height, horizontal_fov_deg); }
  RenderOptions Render(double voxel_size_m) const { return RenderOptions{voxel_size_m, max_depth_m}; }
  RaycasterOptions Raycaster() const {
    RaycasterOptions o;
    o.cloud_cell_m = cloud_cell_m;
    o.point_radius_factor = cloud_radius_factor;
    o.cloud_squares = cloud_squares;
    return o;
  }
};

// Why a view was dropped.
enum class ViewDrop { kKept = 0, kEmpty, kTooClose, kHomogeneous };
const char* ViewDropName(ViewDrop d);  // "kept", "empty", "too_close", "homogeneous"

struct ViewRecord {
  int id = 0;        // Index in ViewSet::views.
  int position = 0;  // Index in ViewSet::positions.
  double yaw_deg = 0, pitch_deg = 0;
  Eigen::Isometry3d world_from_camera = Eigen::Isometry3d::Identity();
  ViewDrop drop = ViewDrop::kKept;
  double hit_fraction = 0;     // Fraction of pixels that hit the scene.
  double median_depth_m = 0;   // Over hit pixels; 0 when none.
  double color_stddev = 0;     // See ViewsOptions::min_color_stddev.
  bool kept() const { return drop == ViewDrop::kKept; }
};

struct ViewSet {
  PinholeCamera camera;
  double voxel_size_m = 0;
  double view_z = 0;                         // Camera height, metres (world z).
  std::vector<Eigen::Vector3d> positions;    // Viewpoints.
  std::vector<ViewRecord> views;             // Position-major; per position the main ring, then the tilted ones.
  std::vector<uint8_t> voxel_seen;           // Per VoxelGrid::Index of the map: 1 when a kept view hit it.
  double seconds_render = 0;                 // Tracing and shading only.
  size_t num_kept() const;
};

// Called for every rendered view (kept or not) in order; an error stops RenderViews and is returned.
using ViewSink = std::function<Status(const ViewRecord&, const RenderedView&)>;

// Viewpoints over the free space of `map` (see the file comment). `view_z` receives the camera height.
// Empty when there is no free voxel with enough clearance.
std::vector<Eigen::Vector3d> PlaceViewpoints(const VoxelMap& map, const ViewsOptions& options, double* view_z);

// Places viewpoints, renders every view, applies the filters and records which map voxels the kept views
// see. Errors when no viewpoint can be placed (the message says which option to relax).
Result<ViewSet> RenderViews(const ViewRenderer& renderer, const VoxelMap& map, const ViewsOptions& options,
                            const ViewSink& sink = {});

// The filter statistics of one rendered view, and the verdict.
void MeasureView(const RenderedView& view, const ViewsOptions& options, ViewRecord* record);
// The k-th smallest of `values` (k < size), the value std::nth_element would put at k; reorders `values`.
// Linear time (a histogram of the float bits, then nth_element on one bucket).
float NthSmallest(std::vector<float>* values, size_t k);

// OUTDIR/views.json: intrinsics, every pose (world_from_camera, 4x4 row-major), kept / dropped and why,
// the filter statistics, and thumbnail names (views/view_NNNNN.png) when thumbnails are written.
// Positions, poses (world_from_camera, yaw_deg, pitch_deg) and camera_z are mapped by `input_from_world`
// (the canonical frame back to the input frame).
std::string ViewsToJson(const ViewSet& views, const ViewsOptions& options, bool with_thumbnails,
                        const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity());
// "views/view_00042.png"
std::string ThumbnailName(int view_id);

// Occupied voxels with a free 6-neighbour (the surface the free space can see), and how many are seen.
struct SurfaceCoverage {
  size_t surface_voxels = 0;
  size_t seen_voxels = 0;
  double fraction() const { return surface_voxels ? double(seen_voxels) / double(surface_voxels) : 0.0; }
};
SurfaceCoverage ComputeSurfaceCoverage(const VoxelGrid& grid, const std::vector<uint8_t>& voxel_seen);

}  // namespace semvox
