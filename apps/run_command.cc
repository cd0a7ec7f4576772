// `semvox run`: the configuration from --config and the flags, the models directory, then the pipeline
// (pipeline/pipeline.h), its outputs, config_used.yaml and report.html.
#include <filesystem>
#include <iostream>

#include "apps/commands.h"
#include "apps/models_dir.h"
#include "core/file_util.h"
#include "core/log.h"
#include "pipeline/onnx_stage.h"
#include "pipeline/pipeline.h"
#include "report/report.h"

namespace semvox {
namespace fs = std::filesystem;

namespace {
// An output directory inside the input's own directory tree is fine; the input file itself must not be
// overwritten by an output.
Status CheckOutputNotInput(const std::string& input, const std::string& outdir) {
  std::error_code ec;
  const fs::path in = fs::weakly_canonical(input, ec);
  const fs::path out = fs::weakly_canonical(outdir, ec);
  if (!ec && in == out) return Status::InvalidInput(FileError(outdir, "output directory is the input file", "choose another -o"));
  return Status::Ok();
}
}  // namespace

Status RunRunCommand(const RunArgs& args) {
  PipelineOptions options;
  PipelineConfig& config = options.config;
  if (!args.config_path.empty()) SEMVOX_RETURN_IF_ERROR(LoadConfigFile(args.config_path, &config));
  if (!args.up.empty()) config.load.up = args.up == "y" ? UpAxis::kY : args.up == "z" ? UpAxis::kZ : UpAxis::kAuto;
  if (args.scale > 0) config.load.scale = args.scale;
  if (args.max_voxels > 0) config.voxelize.max_voxels = size_t(args.max_voxels);
  SEMVOX_RETURN_IF_ERROR(CheckConfig(config));
  SEMVOX_RETURN_IF_ERROR(CheckOutputNotInput(args.input, args.outdir));
  // Only the semantic stage (and the support / clutter and room-type stages after it) reads models.
  if (config.semantic.enabled) {
    Result<std::string> dir = ResolveModelsDir(args.models_dir, args.argv0);
    if (!dir.ok()) return dir.status();
    options.models_dir = std::move(dir).value();
  }
  // Fail on an unwritable OUTDIR before any work.
  SEMVOX_RETURN_IF_ERROR(EnsureWritableDirectory(args.outdir));
  options.onnx = args.onnx;
  if (args.save_views) options.thumbnails_outdir = args.outdir;

  Result<PipelineResult> run = RunPipeline(args.input, options);
  if (!run.ok()) return run.status();
  SEMVOX_RETURN_IF_ERROR(WriteFileAtomic((fs::path(args.outdir) / "config_used.yaml").string(), DumpConfig(config)));
  PipelineSummary summary;
  SEMVOX_RETURN_IF_ERROR(WritePipelineOutputs(*run, args.outdir, &summary));
  // The self-contained HTML report of everything above (src/report).
  const bool semantic = run->labels.has_value();
  ReportSummary report;
  SEMVOX_RETURN_IF_ERROR(WriteReport(args.outdir, config.report, &report));
  // A run without the semantic stage has no voxels.ply: the page says so, no warning needed.
  if (!report.view_3d_absent.empty() && semantic) SEMVOX_WARN("report.html: 3D view not available: " << report.view_3d_absent);
  if (args.json) std::cout << summary.Text();
  SEMVOX_INFO("outputs in " << args.outdir << (semantic ? " (report.html, voxels.ply, map.ot, semantic_topview.png, rooms.geojson, occupancy.pgm/.yaml, map.bt, summary.json, ...)"
                                                        : " (report.html, occupancy.pgm/.yaml, rooms.geojson, map.bt, summary.json)"));
  return Status::Ok();
}

}  // namespace semvox
