// `semvox report OUTDIR [--config FILE.yaml] [--no-3d]`: (re)writes OUTDIR/report.html from the files a
// `semvox run` left there.
#include <filesystem>

#include "apps/commands.h"
#include "apps/config.h"
#include "core/log.h"
#include "report/report.h"

namespace semvox {

Status RunReport(const ReportArgs& args) {
  PipelineConfig config;
  if (!args.config_path.empty()) SEMVOX_RETURN_IF_ERROR(LoadConfigFile(args.config_path, &config));
  ReportOptions options = config.report;
  if (args.no_3d) options.view_3d = false;
  ReportSummary summary;
  SEMVOX_RETURN_IF_ERROR(WriteReport(args.outdir, options, &summary));
  if (!summary.view_3d_absent.empty()) SEMVOX_WARN("report.html: 3D view not available: " << summary.view_3d_absent);
  std::string view = summary.view_3d ? "; 3D view of " + std::to_string(summary.view_3d_voxels) + " voxels" : "";
  if (summary.view_3d && summary.view_3d_merge > 1)
    view += " (" + std::to_string(summary.view_3d_merge) + "x" + std::to_string(summary.view_3d_merge) + "x" +
            std::to_string(summary.view_3d_merge) + " merged)";
  SEMVOX_INFO("wrote " << (std::filesystem::path(args.outdir) / options.output_name).string() << " ("
                       << (summary.bytes + 500000) / 1000000 << " MB" << view << ")");
  return Status::Ok();
}

}  // namespace semvox
