#include "pipeline/views_stage.h"

#include <filesystem>

#include "core/file_util.h"
#include "core/log.h"
#include "io/image_io.h"

namespace semvox {
namespace fs = std::filesystem;

Result<ViewsStageResult> RenderViewsStage(const ViewRenderer& renderer, const VoxelMap& map, const ViewsOptions& options,
                                          const std::string& thumbnails_outdir, const ViewSink& extra_sink) {
  const bool save_views = !thumbnails_outdir.empty();
  if (save_views) SEMVOX_RETURN_IF_ERROR(EnsureWritableDirectory((fs::path(thumbnails_outdir) / "views").string()));
  ViewSink sink = [&](const ViewRecord& record, const RenderedView& view) {
    if (save_views)
      SEMVOX_RETURN_IF_ERROR(WriteImage((fs::path(thumbnails_outdir) / ThumbnailName(record.id)).string(),
                                        DownscaleImage(view.rgb, options.thumbnail_width)));
    if (extra_sink) return extra_sink(record, view);
    return Status::Ok();
  };
  Result<ViewSet> views = RenderViews(renderer, map, options, sink);
  if (!views.ok()) return views.status();
  ViewsStageResult out;
  out.thumbnails = save_views;
  const SurfaceCoverage cov = ComputeSurfaceCoverage(map.grid, views->voxel_seen);
  ViewsStageSummary& summary = out.summary;
  summary.positions = views->positions.size();
  summary.views = views->views.size();
  summary.kept = views->num_kept();
  summary.surface_voxels = cov.surface_voxels;
  summary.seen_surface_voxels = cov.seen_voxels;
  summary.camera_z = views->view_z;
  summary.viewpoints = views->positions;
  summary.seconds_render = views->seconds_render;
  out.views = std::move(views).value();
  SEMVOX_INFO("views: " << summary.positions << " viewpoints at z = " << summary.camera_z << ", " << summary.kept
                        << " of " << summary.views << " views kept; they see " << cov.seen_voxels << " of "
                        << cov.surface_voxels << " surface voxels (" << 100.0 * cov.fraction() << "%)");
  return out;
}

Status WriteViewsJson(const ViewsStageResult& views, const ViewsOptions& options, const std::string& outdir,
                      const Eigen::Isometry3d& input_from_world) {
  return WriteFileAtomic((fs::path(outdir) / "views.json").string(), ViewsToJson(views.views, options, views.thumbnails, input_from_world));
}

}  // namespace semvox
