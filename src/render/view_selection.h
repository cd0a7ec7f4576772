// Choosing the views that add evidence: a greedy multi-cover of the map's surface voxels.
//
//   const std::vector<uint32_t> surface = SurfaceVoxels(map.grid);
//   std::vector<CandidateVisibility> seen = MeasureCandidateVisibility(renderer, map.grid, surface, camera, poses,
//                                                                      render, options);
//   ViewSelection pick = SelectViewsBySetCover(SeenLists(seen), surface.size(), options);
//   for (int c : pick.chosen) ... classify poses[c] ...
//
// Every candidate view is traced once at a reduced resolution (ViewSelectionOptions::visibility_downscale):
// which surface voxels (occupied voxels with a free 6-neighbour) it sees from a good angle (the angle between
// the pixel's ray and the surface normal at most max_incidence_deg). The cover then asks each surface voxel to
// be seen by min_views_per_voxel chosen views, as far as the candidates can: its demand is
// min(k, number of candidates that see it). The greedy rule of Johnson ("Approximation algorithms for
// combinatorial problems", JCSS 1974) for set multi-cover takes, again and again, the view that lowers the
// remaining demand most, ties to the lowest candidate index; it stops when no view lowers it by at least
// min_gain_fraction of the total demand. The gains only shrink as views are taken (the objective is
// submodular), so stale gains are upper bounds and the lazy evaluation of Minoux ("Accelerated greedy
// algorithms for maximizing submodular set functions", 1978) picks exactly the views the plain greedy
// rule picks, in the same order.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "core/option_table.h"
#include "core/voxel_grid.h"
#include "render/camera.h"
#include "render/view_renderer.h"

namespace semvox {

struct ViewSelectionOptions {
  // k of the multi-cover; 4 keeps the voxel label accuracy of classifying every candidate on the validation
  // apartments with a third of the views (docs/speed.md).
  int min_views_per_voxel = 4;
  double max_incidence_deg = 75.0;  // Grazing views give little evidence of a surface.
  // The total demand is the sum over surface voxels of min(k, candidates that see it); 0 takes views until no
  // demand that the candidates can meet is left. 0.005 stops before the last views, which each add a few
  // hundred voxel sightings: on seven generated validation runs the labels are as good as with 0.002 (visible-
  // voxel accuracy 0.7751 -> 0.7759) with 60-65% of the views (docs/speed.md, thirteenth session).
  double min_gain_fraction = 0.005;
  // Same field of view; at 320 x 240 and 60 degrees, 2 gives pixels about a 5 cm voxel wide at 3 m.
  int visibility_downscale = 2;

  // The fields users set (section `semantic`): meaning, unit and range.
  static const OptionTable<ViewSelectionOptions>& Options() {
    using O = ViewSelectionOptions;
    static const OptionTable<O> table = {
        OptionNumber(&O::min_views_per_voxel, "min_views_per_voxel", 1, 100, "",
                     "cover: chosen views that should see each surface voxel (k)"),
        OptionNumber(&O::max_incidence_deg, "max_incidence_deg", 1, 90, "degrees",
                     "cover: a view sees a voxel only when its ray meets the surface at most this far from the normal"),
        OptionNumber(&O::min_gain_fraction, "min_gain_fraction", 0, 0.999999, "",
                     "cover: stop when the best further view meets less than this fraction of the total demand"),
        OptionNumber(&O::visibility_downscale, "visibility_downscale", 1, 16, "",
                     "cover: candidates are traced at 1/this of the classification resolution"),
    };
    return table;
  }
  bool Check(std::string* error) const;
};

// Occupied voxels of `grid` with a free 6-neighbour: the surface the free space can see. Grid indices,
// ascending.
std::vector<uint32_t> SurfaceVoxels(const VoxelGrid& grid);

// What one candidate view sees in the visibility pass.
struct CandidateVisibility {
  std::vector<uint32_t> surface_ids;  // Indices into the surface list seen from a good angle; ascending, unique.
  double hit_fraction = 0;            // Fraction of the pixels that hit the scene.
  double mean_depth_m = 0;            // Over hit pixels; 0 when none.
};

// Traces every pose with `camera` scaled down by options.visibility_downscale (candidates in parallel,
// deterministic). `surface` as SurfaceVoxels(grid) returns it.
std::vector<CandidateVisibility> MeasureCandidateVisibility(const ViewRenderer& renderer, const VoxelGrid& grid,
                                                            const std::vector<uint32_t>& surface, const PinholeCamera& camera,
                                                            const std::vector<Eigen::Isometry3d>& world_from_camera,
                                                            const RenderOptions& render, const ViewSelectionOptions& options);

struct ViewSelection {
  std::vector<int> chosen;       // Candidate indices, ascending.
  size_t candidates = 0;
  size_t surface_voxels = 0;
  size_t coverable_voxels = 0;   // Seen by at least k candidates.
  size_t covered_voxels = 0;     // Seen by at least k chosen views.
  size_t seen_voxels = 0;        // Seen by at least one chosen view.
  // Share of the surface voxels seen by at least k chosen views (0 when there is no surface).
  double coverage() const { return surface_voxels ? double(covered_voxels) / double(surface_voxels) : 0.0; }
  // The same for all candidates together: the most any selection can reach.
  double coverable() const { return surface_voxels ? double(coverable_voxels) / double(surface_voxels) : 0.0; }
};

// The greedy multi-cover above. seen[c]: ascending unique element ids in [0, num_elements) of candidate c.
ViewSelection SelectViewsBySetCover(const std::vector<std::vector<uint32_t>>& seen, size_t num_elements,
                                    const ViewSelectionOptions& options);

}  // namespace semvox
