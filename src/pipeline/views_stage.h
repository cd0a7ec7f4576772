// The render stage of the pipeline: viewpoints and virtual views over the voxel map (render/views.h), with
// what each view saw; views.json written apart.
//
//   Result<ViewsStageResult> views = RenderViewsStage(renderer, map, options, thumbnails_outdir, extra_sink);
//   WriteViewsJson(*views, options, outdir, input_from_world);
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/status.h"
#include "mapping/voxelizer.h"
#include "render/view_renderer.h"
#include "render/views.h"

namespace semvox {

struct ViewsStageSummary {
  size_t positions = 0, views = 0, kept = 0;
  size_t surface_voxels = 0, seen_surface_voxels = 0;  // Occupied voxels with a free neighbour; seen by kept views.
  double camera_z = 0, seconds_build = 0, seconds_render = 0;
  std::vector<Eigen::Vector3d> viewpoints;  // The viewpoints' positions.
};

struct ViewsStageResult {
  ViewSet views;
  ViewsStageSummary summary;
  bool thumbnails = false;  // PNG thumbnails were written (views.json names them).
};

// Renders the views of `map`; `extra_sink` (optional) sees every rendered view too. With a non-empty
// `thumbnails_outdir` each view's PNG thumbnail is written to thumbnails_outdir/ThumbnailName(id)
// (views/view_NNNNN.png) as it is rendered.
Result<ViewsStageResult> RenderViewsStage(const ViewRenderer& renderer, const VoxelMap& map, const ViewsOptions& options,
                                          const std::string& thumbnails_outdir, const ViewSink& extra_sink = {});

// OUTDIR/views.json; positions and poses mapped by `input_from_world` (the canonical frame back to the input frame).
Status WriteViewsJson(const ViewsStageResult& views, const ViewsOptions& options, const std::string& outdir,
                      const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity());

}  // namespace semvox
