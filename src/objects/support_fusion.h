// Fusing per-pixel support / clutter / other probabilities into voxels, through the per-pixel voxel keys of
// the rendered views (render/view_renderer.h), and the stage's exports.
//
//   SupportClutterFusion fusion(options);
//   for (each view) fusion.AddView(view, classified.probabilities);   // w x h x 3, (support, clutter, other)
//   fusion.WritePly(out + "/support_clutter.ply");
//   fusion.WriteTopView(out + "/support_clutter_topview.png", grid);  // on the occupancy grid
//
// A voxel's probabilities are the mean over every pixel (of every view) whose hit lies in it: each pixel is
// one observation of the voxel's surface, so near views, which see a voxel in more pixels, weigh more.
// Label: the argmax when its probability is at least min_label_probability, else other.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/image.h"
#include "core/option_table.h"
#include "core/status.h"
#include "core/voxel_grid.h"
#include "core/voxel_key.h"
#include "render/view_renderer.h"

namespace semvox {

struct SupportFusionOptions {
  double voxel_size_m = 0.05;          // Must equal the RenderOptions::voxel_size_m of the views. > 0.
  double min_label_probability = 0.0;

  // The fields users set (section `objects`): meaning, unit and range.
  static const OptionTable<SupportFusionOptions>& Options() {
    using O = SupportFusionOptions;
    static const OptionTable<O> table = {
        OptionNumber(&O::min_label_probability, "min_label_probability", 0, 1, "",
                     "a voxel is support / clutter only with at least this fused probability"),
    };
    return table;
  }
  bool Check(std::string* error) const;
};

struct SupportVoxel {
  VoxelKey key;
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  std::array<float, 3> p{0, 0, 1};  // support, clutter, other.
  uint8_t label = 0;                // 1 support, 2 clutter, 0 other (support_clutter.ply).
  int observations = 0;             // Pixels fused.
};

class SupportClutterFusion {
 public:
  explicit SupportClutterFusion(const SupportFusionOptions& options = {}) : options_(options) {}

  // `probabilities`: view width x height x 3. Pixels that hit nothing are skipped.
  Status AddView(const RenderedView& view, const std::vector<float>& probabilities);

  // Every observed voxel, in key order.
  std::vector<SupportVoxel> Voxels() const;
  size_t num_voxels() const { return acc_.size(); }
  int num_views() const { return views_; }

  // support_clutter.ply: binary little endian; vertex float x, y, z (voxel centre, metres), uchar label
  // (1 support, 2 clutter, 0 other), float p_support, p_clutter, p_other. Atomic.
  // Voxel centres mapped by `input_from_world` (the canonical frame back to the input frame).
  Status WritePly(const std::string& path, const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity()) const;
  // Top view on the occupancy grid (width dims[0], height dims[1], row 0 = largest y): per column the label
  // of the highest fused support or clutter voxel (support green, clutter red), else the grid's state
  // (occupied dark grey, free white, unknown light grey).
  ImageRgb8 TopView(const VoxelGrid& grid) const;
  Status WriteTopView(const std::string& path, const VoxelGrid& grid) const;

 private:
  struct Acc {
    std::array<double, 3> sum{0, 0, 0};
    int count = 0;
  };
  SupportFusionOptions options_;
  std::unordered_map<uint64_t, Acc> acc_;  // VoxelKey::Pack() -> sums.
  int views_ = 0;
};

}  // namespace semvox
