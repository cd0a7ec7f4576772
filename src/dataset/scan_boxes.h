// Ground truth of a real scan as furniture boxes (library semvox_dataset), in two formats:
//  - the ScanNet style of ../shared/data/scannet_scene0000_00/gt.json:
//      {"axis_align_matrix": [[4x4, row-major: scan (input) frame -> aligned frame]],
//       "boxes_in_aligned_frame": [{"class": "table", "nyu40": 7, "centre_size": [cx, cy, cz, dx, dy, dz]}, ...]}
//    with boxes axis-aligned in the aligned frame, metres;
//  - the SUN RGB-D style of ../shared/data/sunrgbd_000017/gt_boxes.tsv (mmdetection3d's depth boxes): a
//    tab-separated header naming at least class_name, cx, cy, cz, dx, dy, dz and yaw_rad, then one box per
//    line in the scan's own frame: centre, full extents along the box's own axes, turned by yaw_rad
//    (counter-clockwise, radians) about +z. The class name is read as a NYU40 name or alias
//    (core/label_aliases.h: "night_stand" is night stand, 32); no axis_align_matrix (identity).
// ReadBoxGroundTruth takes a path ending in .tsv as the second, anything else as the first. Scored by
// eval/box_eval.h.
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
  Eigen::Vector3d size = Eigen::Vector3d::Zero();    // Full extents along the box's axes, metres, >= 0.
  double yaw_rad = 0;        // The box's axes: the aligned axes turned by this about +z (SUN RGB-D style).
  // Whether the aligned-frame point p lies inside the box (faces included).
  bool Contains(const Eigen::Vector3d& p) const;
};

struct BoxGroundTruth {
  std::string path;                                   // For messages.
  Eigen::Matrix4d axis_align = Eigen::Matrix4d::Identity();  // Input (scan) frame -> aligned frame.
  std::vector<GroundTruthBox> boxes;
};

// Parses gt.json text; `name` names the file in errors. A missing or malformed field gives one
// kInvalidInput line naming the file and the field ("boxes_in_aligned_frame[3].centre_size: expected 6 numbers").
Result<BoxGroundTruth> ParseBoxGroundTruth(const std::string& json_text, const std::string& name);
// Parses a SUN RGB-D style gt_boxes.tsv (above); errors name the file, the line and the column.
Result<BoxGroundTruth> ParseSunRgbdBoxes(const std::string& tsv_text, const std::string& name);
Result<BoxGroundTruth> ReadBoxGroundTruth(const std::string& path);

}  // namespace semvox
