// Scoring a `semvox run` of a real scan against per-point labels (docs/metrics.md, "Real scans: point scores").
//
//   ReadLabelledPoints(LABELLED.ply) + ReadRunVoxels(OUTDIR/voxels.ply) -> EvaluatePoints -> PointEvalReport
//   EvaluateRunAgainstPoints(OUTDIR, LABELLED.ply) adds the room types (rooms.geojson) and seconds (summary.json).
//
// The ground truth is a PLY of points in the scan's own (input) frame with a per-point NYU40 `label`, as
// ../shared/data/s3dis_office_room/office_room.ply: vertex x, y, z (metres) and label (any integer type; 0 =
// unlabelled, skipped). Each labelled point takes the label of the nearest occupied voxel centre within
// kPointMatchRadiusM; a point with no voxel that near counts as wrong (the map missed its surface). Table and
// desk stand for each other, as in the box scores.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/status.h"
#include "eval/box_eval.h"
#include "eval/confidence_eval.h"
#include "eval/evaluate.h"

namespace semvox {

// A labelled point may take the label of a voxel centre at most this far away (metres).
inline constexpr double kPointMatchRadiusM = 0.075;

struct LabelledPoints {
  std::string path;
  std::vector<Eigen::Vector3d> points;  // Input frame, metres; labelled points only.
  std::vector<int> labels;              // NYU40 id of each point (> 0).
};

// A labelled PLY (vertex x, y, z, label). Missing file, missing property, a label outside 0-40, no labelled
// point: kInvalidInput naming the file.
Result<LabelledPoints> ReadLabelledPoints(const std::string& path);

struct PointClassScore {
  int nyu40 = 0;
  size_t points = 0;              // Labelled points of the class.
  size_t correct = 0;
  size_t unmatched = 0;           // No voxel within kPointMatchRadiusM.
  Score recall;                   // correct / points.
  std::vector<LabelCount> top;    // Up to three most frequent predicted labels (0: unmatched), most frequent first.
};

struct PointEvalReport {
  std::string pred_dir, gt_path;
  size_t occupied = 0;                       // Occupied voxels in voxels.ply.
  size_t points = 0;                         // Labelled points scored.
  Score accuracy;                            // Points whose nearest voxel carries their label.
  Score matched;                             // Points with a voxel within kPointMatchRadiusM.
  std::map<int, PointClassScore> per_class;  // Keyed by NYU40 id.
  Score mean_class_recall;                   // Mean of per_class recall.
  Score floor_recall;                        // Recall of the floor's points (class 2); absent without floor points.
  Score wall_share;                          // Share of all occupied voxels labelled wall (1).
  // The confidence of the matched points' voxels, right when the point's label matches, when voxels.ply has a
  // confidence (scored = 0 otherwise).
  ConfidenceScores confidence;
  Score rooms_present;                       // As BoxEvalReport.
  std::vector<RoomFound> rooms;
  std::vector<std::pair<std::string, double>> seconds;
  std::string ToJson() const;
  std::string Table() const;
};

// Scores `voxels` (input frame) against `gt` (input frame). Pure.
PointEvalReport EvaluatePoints(const RunVoxels& voxels, const LabelledPoints& gt);

// Reads OUTDIR/voxels.ply (required), OUTDIR/summary.json and OUTDIR/rooms.geojson (optional) and scores them
// against the labelled PLY.
Result<PointEvalReport> EvaluateRunAgainstPoints(const std::string& pred_dir, const std::string& gt_path);

}  // namespace semvox
