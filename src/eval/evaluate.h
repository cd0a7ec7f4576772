// Scoring `semvox run` outputs against a generated apartment's ground truth (docs/metrics.md).
//
//   Evaluate(pred OUTDIR, gt DIR) -> EvalReport -> eval.json + a printed table
//
// Metrics, each computed only when its prediction file exists (otherwise reported absent, never faked):
//   (a) top-view geometric accuracy (occupancy.pgm) and top-view semantic accuracy (voxels.ply), as in the
//       Voxel-CRF paper (Kim et al.), Tables 1 and 3;
//   (b) visible-voxel semantic accuracy, mean class recall and mean IoU over classes present (voxels.ply),
//       Voxel-CRF Tables 2 and 3;
//   (c) NYU 4-class per-class recall, average and global accuracy on the same voxels (MST-CRF paper, Table 3);
//   (d) room segmentation recall and precision (rooms.png), Bormann et al. 2016;
//   (e) room-type per-pixel accuracy, global and averaged over types (rooms.png + rooms.geojson), the
//       room-labelling paper, Table II.
// The building blocks below take plain images and label maps so that tests can score hand-built cases.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/geometry.h"
#include "core/image.h"
#include "core/status.h"
#include "mapping/occupancy_map.h"
#include "dataset/ground_truth.h"
#include "eval/confidence_eval.h"
#include "eval/score.h"

namespace semvox {

// One ground-truth class of a score: its pixels or voxels, how many got that label, and the labels most often
// predicted there instead (-1 when none; ties to the lower id), for seeing which classes hold a class mean down.
struct ClassRecall {
  size_t count = 0, correct = 0;
  int most_confused_with = -1;
  std::vector<std::pair<int, size_t>> confusions;  // The (up to) three labels most often predicted instead, with their counts.
};

struct TopViewScores {
  Score geometric_accuracy;      // Occupied vs not, over the apartment's footprint.
  Score semantic_accuracy;       // Mean over classes present in the ground truth ("empty" included) of recall.
  Score semantic_global;         // Fraction of footprint pixels with the right label.
  size_t pixels = 0;             // Footprint pixels scored.
  double predicted_unknown = 0;  // Fraction of footprint pixels the occupancy map leaves unknown.
  std::map<int, ClassRecall> per_class;  // Per ground-truth top-view label (NYU40 id, 0 = empty).
  // For people (eval_topview.png), on the ground-truth grid: black both occupied, white both not, red
  // occupied in the ground truth only, blue predicted occupied only, light grey outside the footprint.
  ImageRgb8 geometric_diff;
};

struct VoxelScores {
  Score accuracy;          // Fraction of visible voxels with the right NYU40 label (global).
  Score mean_recall;       // Mean per-class recall over classes present.
  Score mean_iou;          // Mean IoU over classes present in the ground truth.
  size_t visible = 0;      // Ground-truth surface voxels the prediction holds.
  size_t gt_voxels = 0;    // Ground-truth surface voxels.
  std::map<int, double> iou_per_class;  // NYU40 id -> IoU.
  std::map<int, ClassRecall> per_class;  // NYU40 id of the ground truth -> its visible voxels.
  // (c) NYU 4-class: recall of ground, structure, furniture, props; their mean; global accuracy.
  Score nyu4_recall[4];
  Score nyu4_average, nyu4_global;
};

struct RoomSegmentationScores {
  Score recall, precision;
  int gt_rooms = 0, predicted_rooms = 0;
};

struct RoomTypeScores {
  Score global, average;  // Per-pixel accuracy; mean over ground-truth types present of per-type recall.
  std::map<int, double> recall_per_type;
  std::map<int, std::map<int, size_t>> confusion_pixels;  // [ground-truth type][predicted type] (0: none).
};

struct EvalReport {
  std::string pred_dir, gt_dir;
  double voxel_size_m = 0;
  TopViewScores top_view;
  VoxelScores voxels;
  RoomSegmentationScores rooms;        // Against spaces separated by walls (open-plan partners merged).
  RoomSegmentationScores rooms_typed;  // Against typed areas (an open-plan kitchen apart from the living room).
  RoomTypeScores room_types;
  // The confidence of the visible voxels (right when their label is the ground truth's), when voxels.ply has a
  // confidence (scored = 0 otherwise; eval/confidence_eval.h).
  ConfidenceScores confidence;
  std::string ToJson() const;
  std::string Table() const;
};

// --- Building blocks (exposed for tests) ---

// Voxel label maps: packed OctoMap key (VoxelKey::Pack) -> NYU40 label.
using VoxelLabels = std::unordered_map<uint64_t, int>;

// Ground-truth labels of the surface voxels of a labelled mesh at `resolution` on OctoMap keys: the face
// label that most faces passing through a voxel carry (exact triangle-box overlap; ties to the lower id).
VoxelLabels VoxelizeLabeledMesh(const Mesh& mesh, double resolution);

// (a) `gt_topview`: NYU40 label per pixel (0 empty, kTopViewHidden not scored) on `grid`; the footprint
// is where gt_rooms or gt_topview is non-zero. `pred_topview` (may be null): predicted labels on the same grid.
TopViewScores ScoreTopView(const ImageU16& gt_topview, const ImageU16& gt_rooms, const FloorGrid& grid,
                           const OccupancyMap* occupancy, const ImageU16* pred_topview);
// Predicted top-view labels on `grid` from voxel centres: the label of the highest voxel in [z_lo, z_hi).
ImageU16 TopViewFromVoxels(const std::vector<Eigen::Vector3f>& centres, const std::vector<int>& labels,
                           const FloorGrid& grid, double z_lo, double z_hi);
// (b) + (c).
VoxelScores ScoreVoxels(const VoxelLabels& gt, const VoxelLabels& pred);
// (d) `pred_rooms` on `pred_grid` (room ids, 0 none) against `gt_rooms` on `gt_grid`.
RoomSegmentationScores ScoreRoomSegmentation(const ImageU16& gt_rooms, const FloorGrid& gt_grid,
                                             const ImageU16& pred_rooms, const FloorGrid& pred_grid);
// (e) Types per room id (gt_types[id], pred_types[id]; missing ids count as type 0 = unknown). Ground-truth
// rooms of type 0 (untyped: a real plan's entrance or a room whose labels disagree) are not scored.
RoomTypeScores ScoreRoomTypes(const ImageU16& gt_rooms, const FloorGrid& gt_grid, const std::map<int, int>& gt_types,
                              const ImageU16& pred_rooms, const FloorGrid& pred_grid, const std::map<int, int>& pred_types);

// Reads `semvox run` outputs in pred_dir and the ground truth in gt_dir, scores what is there.
Result<EvalReport> Evaluate(const std::string& pred_dir, const std::string& gt_dir);

}  // namespace semvox
