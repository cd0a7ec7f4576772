// summary.json: what a run did (input, frame, voxels, views, rooms, semantic stage, objects, warnings, seconds),
// built in one place from the typed stage results and written last, beside the other outputs. report.html and
// `semvox remove` read it back.
//
//   PipelineSummary summary = SummarizePipeline(result);   // pipeline/pipeline.h
//   Status st = WritePipelineSummary(summary, outdir);       // OUTDIR/summary.json, atomically
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/status.h"

namespace semvox {

struct PipelineResult;  // pipeline/pipeline.h

struct PipelineSummary {
  // The document, keys in summary.json's order: semvox_version, input, bounds, voxel_size_m, grid, voxels,
  // floor, ceiling, frame (with the canonical frame), scan_positions, pocket_positions, enclosed, rays_cast,
  // occupancy, rooms, views, semantic, objects, warnings, seconds, cpu_seconds. Coordinates and heights in the
  // input frame.
  nlohmann::ordered_json json;
  std::string Text() const { return json.dump(2) + "\n"; }  // summary.json's bytes.
};

struct StageTimes;      // pipeline/pipeline.h

// From the run's own seconds and warnings, or from `seconds` and `warnings` (the run's with the writing's).
PipelineSummary SummarizePipeline(const PipelineResult& result);
PipelineSummary SummarizePipeline(const PipelineResult& result, const StageTimes& seconds, const std::vector<std::string>& warnings);

// OUTDIR/summary.json, atomically.
Status WritePipelineSummary(const PipelineSummary& summary, const std::string& outdir);

}  // namespace semvox
