#include "pipeline/semantic_exports.h"

#include <algorithm>
#include <filesystem>
#include <vector>

#include "core/labels.h"
#include "io/image_io.h"
#include "mapping/octomap_io.h"

namespace semvox {
namespace fs = std::filesystem;

Status WriteSemanticExports(const std::string& outdir, const VoxelMap& map, const SemanticLabels& labels, double band_min_m,
                            double band_max_m, const ImageRgb8& occupancy_image, const Eigen::Isometry3d& input_from_world,
                            double min_confidence) {
  const VoxelGrid& grid = map.grid;
  SEMVOX_RETURN_IF_ERROR(WriteVoxelsPly(labels.map, (fs::path(outdir) / "voxels.ply").string(), input_from_world));
  // What the other exports show: the labels at or above the confidence floor, 0 under it.
  SemanticMap floored;
  if (min_confidence > 0) {
    floored = labels.map;
    for (SemanticVoxelRecord& r : floored.occupied)
      if (r.confidence < min_confidence) r.label = 0;
  }
  const SemanticMap& shown = min_confidence > 0 ? floored : labels.map;
  // map.ot: every known voxel of the refined map; occupied ones with label and confidence.
  std::vector<SemanticVoxel> voxels;
  std::vector<int32_t> record(grid.size(), -1);
  for (size_t k = 0; k < labels.map.occupied.size(); ++k) record[labels.map.occupied[k].voxel] = int32_t(k);
  const auto& d = grid.dims();
  for (int iz = 0; iz < d[2]; ++iz)
    for (int iy = 0; iy < d[1]; ++iy)
      for (int ix = 0; ix < d[0]; ++ix) {
        const size_t i = grid.Index(ix, iy, iz);
        const VoxelState st = labels.refined.state(i);
        if (st == VoxelState::kUnknown) continue;
        SemanticVoxel v;
        v.key = grid.KeyOf(ix, iy, iz);
        v.occupied = st == VoxelState::kOccupied;
        if (record[i] >= 0) v.label = shown.occupied[size_t(record[i])].label, v.confidence = shown.occupied[size_t(record[i])].confidence;
        voxels.push_back(v);
      }
  SEMVOX_RETURN_IF_ERROR(WriteSemanticOctree(voxels, grid.resolution(), (fs::path(outdir) / "map.ot").string()));
  const ImageU16 top = SemanticTopView(shown, grid, map.floor_z, band_min_m, band_max_m);
  SEMVOX_RETURN_IF_ERROR(WriteImage((fs::path(outdir) / "semantic_topview_labels.png").string(), top));
  SEMVOX_RETURN_IF_ERROR(WriteImage((fs::path(outdir) / "semantic_topview.png").string(),
                                    ColourSemanticTopView(top, occupancy_image, /*show_unlabelled=*/min_confidence > 0)));
  return Status::Ok();
}

nlohmann::ordered_json SemanticSummaryJson(const SemanticStageOptions& options, const SemanticModels& models,
                                           const SemanticEvidence& evidence, const SemanticLabels& labels) {
  nlohmann::ordered_json j;
  j["model"] = !models.crf_file.empty() ? "models/" + models.crf_file : std::string("untrained defaults");
  j["classification_views"] = evidence.classification_views;
  nlohmann::ordered_json sel = {{"method", ClassifyViewSelectionName(options.view_selection)},
                                 {"candidates", evidence.selection.candidates},
                                 {"width", options.classify_width},
                                 {"height", options.classify_height}};
  if (options.view_selection == ClassifyViewSelection::kCover || options.view_selection == ClassifyViewSelection::kAllObjectsOnCover) {
    const auto share = [&](size_t n) { return evidence.selection.surface_voxels ? double(n) / double(evidence.selection.surface_voxels) : 0.0; };
    sel["chosen"] = evidence.selection.chosen.size();
    sel["hooked_views"] = evidence.hooked_views;  // Classified views the support / clutter stage saw.
    sel["min_views_per_voxel"] = options.selection.min_views_per_voxel;
    sel["max_incidence_deg"] = options.selection.max_incidence_deg;
    sel["surface_voxels"] = evidence.selection.surface_voxels;
    sel["coverage"] = evidence.selection.coverage();            // Seen >= k times by the chosen views.
    sel["coverage_candidates"] = evidence.selection.coverable();  // ... by all candidates.
    sel["seen_once"] = share(evidence.selection.seen_voxels);
  }
  j["view_selection"] = sel;
  j["skipped_classification_views"] = evidence.skipped_views;
  const auto holding_points = std::count(evidence.nodes.holds_point.begin(), evidence.nodes.holds_point.end(), uint8_t(1));
  j["nodes"] = {{"total", evidence.nodes.size()},
                {"occupied", evidence.nodes.count_state(VoxelState::kOccupied)},
                {"free", evidence.nodes.count_state(VoxelState::kFree)},
                {"unknown", evidence.nodes.count_state(VoxelState::kUnknown)},
                {"holding_points", holding_points},
                {"kept_occupied", options.crf.keep_scan_points ? holding_points : 0}};
  j["rays"] = evidence.voxels.rays.size();
  j["planes"] = labels.crf.num_planes;
  j["object_cliques"] = labels.crf.num_object_cliques;
  nlohmann::ordered_json its = nlohmann::ordered_json::array();
  for (const auto& it : labels.crf.iterations)
    its.push_back({{"energy_initial", it.energy_initial}, {"energy_final", it.energy_final}, {"energy_per_sweep", it.energy_per_sweep},
                   {"sweeps", it.sweeps}, {"edges", it.edges}, {"cliques", it.cliques}, {"movable_nodes", it.movable_nodes}, {"changed_labels", it.changed_labels},
                   {"changed_visibility", it.changed_visibility}, {"seconds", it.seconds},
                   {"phase_seconds", {{"build", it.seconds_build}, {"energy", it.seconds_energy}, {"alpha_expansion", it.seconds_expansion},
                                      {"max_flow", it.seconds_max_flow}, {"visibility", it.seconds_visibility}}}});
  j["iterations"] = its;
  if (evidence.view_pixels > 0)
    j["view_appearance"] = {{"classified_pixels", evidence.view_pixels},
                            {"unfamiliar_pixels", evidence.unfamiliar_view_pixels},
                            {"unfamiliar_share", double(evidence.unfamiliar_view_pixels) / double(evidence.view_pixels)}};
  j["object_segments"] = evidence.num_segments >= 0 ? nlohmann::ordered_json(evidence.num_segments) : nlohmann::ordered_json("no model");
  if (evidence.num_segments >= 0 && evidence.unfamiliar_segment_voxels >= 0) {
    const double share = evidence.segment_voxels > 0 ? double(evidence.unfamiliar_segment_voxels) / double(evidence.segment_voxels) : 0.0;
    j["object_segment_shapes"] = {{"segment_voxels", evidence.segment_voxels},
                                  {"unfamiliar_voxels", evidence.unfamiliar_segment_voxels},
                                  {"unfamiliar_share", share},
                                  {"unfamiliar_segments", evidence.unfamiliar_segments},
                                  {"familiar_distance", evidence.familiar_distance}};
  }
  if (options.other_labels)
    j["other_labels"] = models.other ? nlohmann::ordered_json{{"segments", labels.other_segments}, {"voxels", labels.other_voxels}}
                                     : nlohmann::ordered_json("no model");
  if (options.item_labels)
    j["item_labels"] = models.items ? nlohmann::ordered_json{{"items", labels.item_groups}, {"voxels", labels.item_voxels}}
                                    : nlohmann::ordered_json("no model");
  if (options.floor_surface) j["floor_surface"] = {{"relabelled_voxels", labels.floor_surface_voxels}};
  if (options.furniture_feet) j["furniture_feet"] = {{"relabelled_voxels", labels.furniture_feet_voxels}};
  if (options.bar_tables && evidence.num_segments >= 0)
    j["bar_tables"] = {{"segments", labels.bar_table_segments}, {"relabelled_voxels", labels.bar_table_voxels}};
  if (options.counter_min_top_m > 0 && evidence.num_segments >= 0)
    j["low_counters"] = {{"min_top_m", options.counter_min_top_m}, {"segments", evidence.low_counter_segments},
                         {"voxels", evidence.low_counter_voxels}};
  if (evidence.room_views_measured > 0)
    j["room_view_appearance"] = {{"views", evidence.room_views_measured},
                                 {"unfamiliar_views", evidence.room_views_unfamiliar},
                                 {"discounted", options.room_view_familiarity},
                                 {"mean_weight", evidence.room_view_weight_sum / double(evidence.room_views_measured)}};
  if (options.min_confidence > 0) {
    size_t below = 0;
    for (const SemanticVoxelRecord& r : labels.map.occupied) below += r.confidence < options.min_confidence;
    j["min_confidence"] = {{"value", options.min_confidence}, {"voxels_below", below}};
  }
  j["occupied_voxels"] = labels.map.occupied.size();
  j["completed_voxels"] = labels.map.completed_count();
  nlohmann::ordered_json hist = nlohmann::ordered_json::object();
  for (const auto& [label, count] : labels.map.LabelCounts())
    hist[label > 0 && label < kNumNyu40 ? Nyu40Labels()[size_t(label)].name : std::to_string(label)] = count;
  j["labels"] = hist;
  j["seconds"] = {{"depth_evidence", evidence.seconds_depth}, {"view_selection", evidence.seconds_selection}, {"classify", evidence.seconds_classify}, {"crf", labels.crf.seconds},
                  {"crf_planes", labels.crf.seconds_planes}, {"crf_ray_starts", labels.crf.seconds_ray_starts},
                  {"crf_confidence", labels.crf.seconds_confidence}, {"object_segments", evidence.seconds_segments},
                  {"solve_total", labels.seconds}, {"wall_openings", labels.seconds_openings},
                  {"other_labels", labels.seconds_other},
                  {"item_labels", labels.seconds_items}};
  j["files"] = {"voxels.ply", "map.ot", "semantic_topview.png", "semantic_topview_labels.png"};
  return j;
}

}  // namespace semvox
