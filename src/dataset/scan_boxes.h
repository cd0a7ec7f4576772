// Ground truth of a real scan as furniture boxes (library semvox_dataset), the ScanNet style of
// ../shared/data/scannet_scene0000_00/gt.json:
//   {"axis_align_matrix": [[4x4, row-major: scan (input) frame -> aligned frame]],
//    "boxes_in_aligned_frame": [{"class": "table", "nyu40": 7, "centre_size": [cx, cy, cz, dx, dy, dz]}, ...]}
// with boxes axis-aligned in the aligned frame, metres. Scored by eval/box_eval.h.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/status.h"

namespace semvox {

struct GroundTruthBox {
  std::string class_name;    // As in gt.json ("table", "garbagebin", ...), free text.
  int nyu40 = 0;             // NYU40 id, 1..40.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // Aligned frame, metres.
  Eigen::Vector3d size = Eigen::Vector3d::Zero();    // Full extents along the aligned axes, metres, >= 0.
};

struct BoxGroundTruth {
  std::string path;                                   // For messages.
  Eigen::Matrix4d axis_align = Eigen::Matrix4d::Identity();  // Input (scan) frame -> aligned frame.
  std::vector<GroundTruthBox> boxes;
};

// Parses gt.json text; `name` names the file in errors. A missing or malformed field gives one
// kInvalidInput line naming the file and the field ("boxes_in_aligned_frame[3].centre_size: expected 6 numbers").
Result<BoxGroundTruth> ParseBoxGroundTruth(const std::string& json_text, const std::string& name);
Result<BoxGroundTruth> ReadBoxGroundTruth(const std::string& path);

}  // namespace semvox
