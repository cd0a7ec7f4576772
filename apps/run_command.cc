// `semvox run`: the configuration from --config and the flags, the models directory, then the pipeline
// (pipeline/pipeline.h), its outputs, config_used.yaml and report.html.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "apps/commands.h"
#include "apps/models_dir.h"
#include "core/file_util.h"
#include "core/labels.h"
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
std::string Percent(double f) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%.0f %%", 100.0 * f);
  return buf;
}

// The end of a run for its user: the rooms, the main classes, how confident the labels are, the warnings, where the
// outputs are (notes: silenced by -q; the detail of each step is -v's).
void PrintRunSummary(const PipelineResult& run, const PipelineSummary& summary, const std::string& outdir) {
  if (run.room_types && !run.room_types->described.empty()) {
    std::ostringstream rooms;
    for (const RoomDescription& r : run.room_types->described) {
      const int t = r.type_id;
      rooms << (rooms.tellp() > 0 ? "; " : "") << (t > 0 && t < kNumRoomTypes ? RoomTypes()[size_t(t)].name : "unknown");
      if (t > 0) rooms << " (p " << std::fixed << std::setprecision(2) << r.type_probability << ")";
      rooms << " " << std::fixed << std::setprecision(1) << r.area_m2 << " m2";
    }
    SEMVOX_NOTE("rooms: " << run.room_types->described.size() << ": " << rooms.str());
  } else if (const auto rooms = summary.json.find("rooms"); rooms != summary.json.end() && rooms->contains("rooms")) {
    SEMVOX_NOTE("rooms: " << (*rooms)["rooms"].dump() << " (untyped: the room types need the semantic stage)");
  }
  if (run.labels && !run.labels->map.occupied.empty()) {
    const auto& voxels = run.labels->map.occupied;
    std::map<int, size_t> counts;
    size_t above05 = 0, above08 = 0;
    for (const SemanticVoxelRecord& v : voxels) {
      ++counts[v.label];
      above05 += v.confidence >= 0.5f, above08 += v.confidence >= 0.8f;
    }
    std::vector<std::pair<size_t, int>> order;
    for (const auto& [label, n] : counts) order.push_back({n, label});
    std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
    std::ostringstream classes;
    const double total = double(voxels.size());
    for (size_t i = 0; i < order.size() && i < 8; ++i) {
      const int l = order[i].second;
      classes << (i ? ", " : "") << (l > 0 && l < kNumNyu40 ? Nyu40Labels()[size_t(l)].name : "unlabelled") << " "
              << Percent(double(order[i].first) / total);
    }
    SEMVOX_NOTE("labels: " << voxels.size() << " occupied voxels, " << counts.size() << " classes: " << classes.str()
                           << (order.size() > 8 ? ", ..." : ""));
    SEMVOX_NOTE("confidence: " << Percent(double(above05) / total) << " of the voxels at 0.5 or more, " << Percent(double(above08) / total)
                               << " at 0.8 or more (the Voxel-CRF's own measure, not calibrated)");
  }
  const auto warnings = summary.json.find("warnings");
  if (warnings != summary.json.end() && !warnings->empty())
    SEMVOX_NOTE(warnings->size() << " warning" << (warnings->size() > 1 ? "s" : "") << " (above; summary.json lists them)");
  const auto seconds = summary.json.find("seconds");
  if (seconds != summary.json.end() && seconds->contains("total"))
    SEMVOX_NOTE("done in " << std::fixed << std::setprecision(1) << (*seconds)["total"].get<double>() << " s");
  SEMVOX_NOTE("outputs in " << outdir << (run.labels ? ": report.html, voxels.ply, map.ot, semantic_topview.png, rooms.geojson, occupancy.pgm/.yaml, map.bt, summary.json, ..."
                                                      : ": report.html, occupancy.pgm/.yaml, rooms.geojson, map.bt, summary.json"));
}

}  // namespace

Status RunRunCommand(const RunArgs& args) {
  PipelineOptions options;
  PipelineConfig& config = options.config;
  if (!args.config_path.empty()) SEMVOX_RETURN_IF_ERROR(LoadConfigFile(args.config_path, &config));
  if (!args.up.empty() && !ParseUpAxis(args.up, &config.load.up))
    return Status::InvalidInput("--up " + args.up + ": not an axis (hint: auto, z, y, -y, x, -x, -z)");
  if (args.scale > 0) config.load.scale = args.scale;
  if (args.max_voxels > 0) config.voxelize.max_voxels = size_t(args.max_voxels);
  if (args.min_confidence >= 0) config.semantic.min_confidence = args.min_confidence;
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
  PrintRunSummary(*run, summary, args.outdir);
  return Status::Ok();
}

}  // namespace semvox
