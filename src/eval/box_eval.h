// Scoring a `semvox run` of a real scan against furniture boxes (docs/metrics.md, "Real scans: box scores").
//
//   ReadBoxGroundTruth(gt.json) + ReadRunVoxels(OUTDIR/voxels.ply) -> EvaluateBoxes -> BoxEvalReport
//   EvaluateRunAgainstBoxes(OUTDIR, gt.json) adds the room types (rooms.geojson) and seconds (summary.json).
//
// The ground truth is the ScanNet style used in ../shared/data/scannet_scene0000_00/gt.json:
//   {"axis_align_matrix": [[4x4, row-major: scan (input) frame -> aligned frame]],
//    "boxes_in_aligned_frame": [{"class": "table", "nyu40": 7, "centre_size": [cx, cy, cz, dx, dy, dz]}, ...]}
// with boxes axis-aligned in the aligned frame, metres. Real scans have no per-voxel ground truth, so the
// scores are coarse: which labels the voxels inside each box carry, whether the floor is floor, how much of
// the map is wall, which room types were found.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <map>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "core/status.h"
#include "dataset/scan_boxes.h"
#include "eval/confidence_eval.h"
#include "eval/evaluate.h"

namespace semvox {


// The occupied voxels of a run: centres in the input frame (metres) and NYU40 labels.
struct RunVoxels {
  std::vector<Eigen::Vector3d> centres;
  std::vector<int> labels;
  double voxel_size_m = 0.05;  // Edge length; sets the bins of the floor-height estimate.
  std::vector<float> confidence;  // Per voxel, when voxels.ply has a `confidence` property; else empty.
};

// voxels.ply of `semvox run` (vertex x, y, z, label; other properties ignored). Missing file, missing
// label property: kInvalidInput naming the file.
Result<RunVoxels> ReadRunVoxels(const std::string& voxels_ply, double voxel_size_m = 0.05);

struct LabelCount {
  int label = 0;      // NYU40 id.
  size_t count = 0;   // Voxels.
};

struct BoxScore {
  std::string class_name;
  int nyu40 = 0;
  size_t voxels = 0;                // Occupied voxels whose centre lies inside the box (faces included).
  size_t correct = 0;               // Of those, labelled with the box's label (table and desk stand for each other).
  Score recall;                     // correct / voxels; absent when the box holds no voxel.
  std::vector<LabelCount> top;      // Up to three most frequent predicted labels, most frequent first (ties: lower id).
};

struct ClassScore {
  int nyu40 = 0;
  int boxes = 0;          // Boxes of the class.
  size_t voxels = 0;      // Voxels pooled over the class's boxes (a voxel in two boxes counts twice).
  size_t correct = 0;
  Score recall;           // correct / voxels; absent when no box of the class holds a voxel.
};

struct RoomFound {
  int id = 0;
  std::string type;      // Room type name, as rooms.geojson's `type`.
  double area_m2 = 0;    // Floor area, m².
};

struct BoxEvalReport {
  std::string pred_dir, gt_path;
  size_t occupied = 0;                          // Occupied voxels in voxels.ply.
  std::vector<BoxScore> boxes;                  // In gt.json order.
  std::map<std::string, ClassScore> per_class;  // Keyed by gt.json's class name.
  Score mean_box_recall;                        // Mean of per-box recall over boxes holding >= 1 voxel.
  int boxes_scored = 0;                         // Boxes holding >= 1 voxel.
  // Floor band: aligned-frame z in [floor_z_m, floor_z_m + kFloorBandM), voxels inside any box excluded.
  double floor_z_m = 0;                         // Estimated floor height, aligned frame, metres.
  size_t floor_band_voxels = 0;
  Score floor_recall;                           // Share labelled floor (2) in the band.
  Score wall_share;                             // Share of all occupied voxels labelled wall (1).
  // The confidence of the voxels scored (inside a box: right when they carry its label; in the floor band: right
  // when floor), when voxels.ply has a confidence (scored = 0 otherwise).
  ConfidenceScores confidence;
  // From rooms.geojson and summary.json (EvaluateRunAgainstBoxes only).
  Score rooms_present;                          // Absent when rooms.geojson is missing; value unused.
  std::vector<RoomFound> rooms;
  std::vector<std::pair<std::string, double>> seconds;  // summary.json "seconds": stage -> s, file order.
  std::string ToJson() const;
  std::string Table() const;
};

// Height of the floor band above the estimated floor, metres.
inline constexpr double kFloorBandM = 0.10;
// A z level is "dense" when it holds at least this share of the voxels of the most populated level.
inline constexpr double kFloorLevelShare = 0.25;

// Floor height (aligned frame, metres) from aligned-frame voxel centre heights: centres are binned into
// levels of `voxel_size_m` (bin centres on the lowest centre's lattice); the floor is the lower face of the
// lowest level holding >= kFloorLevelShare of the voxels of the most populated level. 0 for no voxel.
double EstimateFloorHeight(const std::vector<double>& z, double voxel_size_m);

// Scores `voxels` (input frame) against `gt` after transforming them by gt.axis_align. Pure.
BoxEvalReport EvaluateBoxes(const RunVoxels& voxels, const BoxGroundTruth& gt);

// rooms.geojson -> the rooms' ids, types and areas (features' properties id, type, area_m2).
Result<std::vector<RoomFound>> ReadRoomsFound(const std::string& rooms_geojson);
// summary.json -> its "seconds" object (stage -> seconds), in file order; empty when there is none.
// `voxel_size_m` (may be null) receives summary.json's voxel_size_m when it is a positive number.
Result<std::vector<std::pair<std::string, double>>> ReadRunSeconds(const std::string& summary_json, double* voxel_size_m = nullptr);

// Table (7) and desk (14) stand for each other; other labels only for themselves.
bool LabelsMatch(int predicted, int truth);
// The NYU40 name of an id ("id N" outside 0-40).
std::string LabelName(int id);

// What a run's directory says beside its voxels: summary.json's voxel size and seconds, rooms.geojson's rooms.
struct RunExtras {
  double voxel_size_m = 0.05;
  std::vector<std::pair<std::string, double>> seconds;
  Score rooms_present;  // Absent when rooms.geojson is missing.
  std::vector<RoomFound> rooms;
};
// OUTDIR must be a directory; summary.json and rooms.geojson are optional.
Result<RunExtras> ReadRunExtras(const std::string& pred_dir);
// OUTDIR/voxels.ply at the voxel size `extras` read.
Result<RunVoxels> ReadRunVoxels(const std::string& pred_dir, const RunExtras& extras);
// A real-scan report (BoxEvalReport, PointEvalReport) takes the run's directory, seconds and rooms.
template <class Report>
void AttachRunExtras(const std::string& pred_dir, RunExtras&& extras, Report* report) {
  report->pred_dir = pred_dir;
  report->seconds = std::move(extras.seconds);
  report->rooms = std::move(extras.rooms);
  report->rooms_present = extras.rooms_present;
}
// The "rooms:" and "run seconds:" lines of the eval tables.
void AppendRoomsAndSeconds(const Score& rooms_present, const std::vector<RoomFound>& rooms,
                           const std::vector<std::pair<std::string, double>>& seconds, std::ostream& os);

// Reads OUTDIR/voxels.ply (required), OUTDIR/summary.json (voxel size and seconds; optional) and
// OUTDIR/rooms.geojson (optional; rooms_present absent without it) and scores them against gt.json.
Result<BoxEvalReport> EvaluateRunAgainstBoxes(const std::string& pred_dir, const std::string& gt_path);

}  // namespace semvox
