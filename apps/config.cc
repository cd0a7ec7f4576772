#include "apps/config.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <functional>
#include <sstream>
#include <vector>

#include "core/file_util.h"

namespace semvox {
namespace {

// One configurable field: where it lives, how to read and print it, its allowed range and its meaning.
struct Field {
  std::string section, key, doc;
  double min, max;  // Inclusive range for numbers.
  std::function<double(const PipelineConfig&)> get;
  std::function<void(PipelineConfig&, double)> set;
  bool is_integer = false;
  // String-valued fields (enums) use these instead.
  std::vector<std::string> choices;
  std::function<std::string(const PipelineConfig&)> get_str;
  std::function<void(PipelineConfig&, const std::string&)> set_str;
};

#define SEMVOX_DOUBLE_FIELD(sec, member, name, lo, hi, doc)                                       \
  Field { sec, #name, doc, lo, hi, [](const PipelineConfig& c) { return double(c.member.name); }, \
          [](PipelineConfig& c, double v) { c.member.name = v; }, false, {}, {}, {} }
// A true / false field (printed and read as the words).
#define SEMVOX_BOOL_FIELD(sec, member, name, text)                                                                     \
  [] {                                                                                                                 \
    Field b;                                                                                                           \
    b.section = sec, b.key = #name, b.doc = text, b.choices = {"true", "false"};                                       \
    b.get_str = [](const PipelineConfig& c) { return std::string(c.member.name ? "true" : "false"); };                 \
    b.set_str = [](PipelineConfig& c, const std::string& v) { c.member.name = v == "true"; };                          \
    return b;                                                                                                          \
  }()
#define SEMVOX_INT_FIELD(sec, member, name, lo, hi, doc)                                          \
  Field { sec, #name, doc, lo, hi, [](const PipelineConfig& c) { return double(c.member.name); }, \
          [](PipelineConfig& c, double v) { c.member.name = decltype(c.member.name)(v); }, true, {}, {}, {} }

const std::vector<Field>& Fields() {
  static const std::vector<Field> kFields = [] {
    std::vector<Field> f;
    {
      Field up;
      up.section = "input";
      up.key = "up";
      up.doc = "up axis of the input file: auto (+Y for glTF, +Z otherwise), z or y";
      up.choices = {"auto", "z", "y"};
      up.get_str = [](const PipelineConfig& c) {
        return std::string(c.load.up == UpAxis::kAuto ? "auto" : c.load.up == UpAxis::kZ ? "z" : "y");
      };
      up.set_str = [](PipelineConfig& c, const std::string& v) {
        c.load.up = v == "z" ? UpAxis::kZ : v == "y" ? UpAxis::kY : UpAxis::kAuto;
      };
      f.push_back(up);
    }
    f.push_back(SEMVOX_DOUBLE_FIELD("input", load, scale, 1e-6, 1e6, "multiplies coordinates into metres (0.001 for mm)"));
    f.push_back(SEMVOX_BOOL_FIELD("input", load, canonical_frame,
                                  "level the scan, turn its walls onto the x / y axes and put the floor at z = 0 before mapping "
                                  "(coordinate outputs stay in the input frame; false: use the input frame as it is)"));
    f.push_back(SEMVOX_DOUBLE_FIELD("input", load, millimetre_warning_extent_m, 1, 1e9,
                                    "warn about units when the scene is larger than this, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("mapping", voxelize, voxel_size_m, 0.005, 1.0, "voxel edge, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("mapping", voxelize, scan_spacing_m, 0.05, 100, "spacing of virtual scan positions, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("mapping", voxelize, scan_height_m, 0.1, 10, "scanner height above the floor, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("mapping", voxelize, scan_clearance_m, 0, 5, "free radius around a scan position, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("mapping", voxelize, max_range_m, 0.1, 1000, "scanner range, metres"));
    f.push_back(SEMVOX_INT_FIELD("mapping", voxelize, enclosure_directions, 4, 360, "horizontal rays testing that a position is indoors"));
    f.push_back(SEMVOX_DOUBLE_FIELD("mapping", voxelize, min_enclosed_fraction, 0, 1, "fraction of those rays that must hit a surface"));
    f.push_back(SEMVOX_DOUBLE_FIELD("mapping", voxelize, horizontal_normal_deg, 0.1, 89, "max tilt of floor/ceiling surfaces, degrees"));
    f.push_back(SEMVOX_DOUBLE_FIELD("mapping", voxelize, min_floor_to_ceiling_m, 0.5, 20, "min ceiling height above the floor, metres"));
    f.push_back(SEMVOX_INT_FIELD("mapping", voxelize, max_voxels, 1, 1e12, "refuse voxel grids larger than this"));
    f.push_back(SEMVOX_INT_FIELD("mapping", voxelize, cloud_normal_neighbors, 3, 100, "k for point-cloud normals"));
    f.push_back(SEMVOX_INT_FIELD("mapping", voxelize, pocket_rounds, 0, 10,
                                 "rounds of extra scan positions in unseen clear pockets (closets, WCs) the grid missed; 0 = off"));
    f.push_back(SEMVOX_INT_FIELD("mapping", voxelize, max_pocket_positions, 1, 100000, "extra positions per round at most, largest pockets first"));
    f.push_back(SEMVOX_DOUBLE_FIELD("occupancy", occupancy, band_min_above_floor_m, -10, 10, "height band bottom above the floor, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("occupancy", occupancy, band_max_above_floor_m, -10, 10, "height band top above the floor, metres"));
    // ---- rooms: floor plan and room segmentation (rooms/floor_plan.h, rooms/room_segmentation.h) ----
    {
      Field method;
      method.section = "rooms";
      method.key = "method";
      method.doc = "room segmentation method (distance: doorway-aware distance watershed; morphological: erosion + growth)";
      method.choices = RoomSegmentationMethodNames();
      method.get_str = [](const PipelineConfig& c) { return std::string(RoomSegmentationMethodName(c.rooms.method)); };
      method.set_str = [](PipelineConfig& c, const std::string& v) { ParseRoomSegmentationMethod(v, &c.rooms.method); };
      f.push_back(method);
    }
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", rooms, max_opening_width_m, 0.1, 20, "widest opening that separates rooms, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", rooms, saddle_ratio, 0.01, 1, "distance: a pass separates rooms below this fraction of the smaller room's inscribed radius"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", rooms, saddle_ratio_larger, 0.01, 1, "distance: ... or of the larger room's inscribed radius"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", rooms, min_room_radius_m, 0, 10, "distance: rooms need at least this inscribed radius, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", rooms, wall_gap_max_m, 0, 20, "distance: gaps from a thin wall's end straight on to an obstacle up to this long are candidate room borders, metres (0 = off)"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", rooms, wall_gap_ratio, 0.01, 100, "distance: such a border separates rooms below this ratio of its half length to the smaller room's inscribed radius"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", rooms, min_room_area_m2, 0, 1000, "smaller rooms merge into a neighbour, m2"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", rooms, min_seed_area_m2, 0.01, 1000, "morphological: pieces split by the erosion stay rooms when both cover this, m2"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", rooms, max_speck_distance_m, 0, 10, "unreached free cells join the nearest room within this, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", floor_plan, door_min_width_m, 0.1, 10, "narrowest door opening, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", floor_plan, door_max_width_m, 0.1, 10, "widest door opening (lintel detection), metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", floor_plan, door_min_height_m, 0.5, 10, "lowest lintel underside above the floor, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", floor_plan, lintel_ceiling_gap_m, 0, 5, "a lintel ends at least this far below the ceiling, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", floor_plan, wall_min_height_m, 0.5, 10, "obstacles reaching this high are walls, not furniture, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", floor_plan, ceiling_step_m, 0, 5, "a ceiling height change this large between two ceiling zones is a room border, metres (0 = off)"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", floor_plan, ceiling_zone_min_area_m2, 0, 1000, "... when both zones cover this area, m2"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", floor_plan, clutter_max_area_m2, 0, 100, "2D maps: obstacle islands up to this area are furniture, m2"));
    f.push_back(SEMVOX_DOUBLE_FIELD("rooms", floor_plan, clutter_max_length_m, 0, 100, "2D maps: ... and up to this bounding-box diagonal, metres"));
    f.push_back(SEMVOX_INT_FIELD("rooms", floor_plan, free_threshold, 0, 254, "2D maps: grey values above this are free"));
    // ---- end rooms ----
    // ---- room_types: the room-type CRF (rooms/room_type_crf.h) ----
    {
      Field scene;
      scene.section = "room_types";
      scene.key = "scene";
      scene.doc = "scene potential: cnn (Eq. 2, s_y) or conf (Eq. 3, with the training confusion)";
      scene.choices = {"cnn", "conf"};
      scene.get_str = [](const PipelineConfig& c) { return std::string(ScenePotentialName(c.room_types.variant.scene)); };
      scene.set_str = [](PipelineConfig& c, const std::string& v) { ParseScenePotential(v, &c.room_types.variant.scene); };
      f.push_back(scene);
      Field hom;
      hom.section = "room_types";
      hom.key = "homogeneity";
      hom.doc = "homogeneity potential (Eq. 6-7): none, stat (learned distance statistics) or gauss (fixed costs x Gaussian)";
      hom.choices = {"none", "stat", "gauss"};
      hom.get_str = [](const PipelineConfig& c) { return std::string(HomogeneityPotentialName(c.room_types.variant.homogeneity)); };
      hom.set_str = [](PipelineConfig& c, const std::string& v) { ParseHomogeneityPotential(v, &c.room_types.variant.homogeneity); };
      f.push_back(hom);
    }
    f.push_back(SEMVOX_INT_FIELD("room_types", room_types.variant, objects, 0, 1, "object-occurrence potential (Eq. 4-5): 1 on, 0 off"));
    f.push_back(SEMVOX_DOUBLE_FIELD("room_types", room_types, cell_size_m, 0.05, 5, "CRF node size, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("room_types", room_types, max_pair_distance_m, 0.1, 50, "homogeneity pairs up to this far apart, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("room_types", room_types, gauss_sigma_m, 0.01, 50, "phi_gauss kernel width, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("room_types", room_types, gauss_same_segment, 0, 100, "phi_gauss: reward for equal types in one segment"));
    f.push_back(SEMVOX_DOUBLE_FIELD("room_types", room_types, gauss_other_segment, 0, 100, "phi_gauss: ... in different segments"));
    f.push_back(SEMVOX_DOUBLE_FIELD("room_types", room_types, object_sigma_m, 0.01, 50, "reach of an object's evidence, metres"));
    f.push_back(SEMVOX_INT_FIELD("room_types", room_types, burn_in_sweeps, 0, 100000, "Gibbs sweeps discarded"));
    f.push_back(SEMVOX_INT_FIELD("room_types", room_types, sample_sweeps, 1, 1000000, "Gibbs sweeps counted into the marginals"));
    f.push_back(SEMVOX_INT_FIELD("room_types", room_types, seed, 0, 4294967295.0, "seed of the Gibbs sampler"));
    f.push_back(SEMVOX_DOUBLE_FIELD("room_types", room_types, min_split_area_m2, 0, 10000, "a room is split only off areas this large, m2"));
    f.push_back(SEMVOX_DOUBLE_FIELD("room_types", room_types, min_split_fraction, 0, 1, "... covering this fraction of the room"));
    f.push_back(SEMVOX_DOUBLE_FIELD("room_types", room_types, min_split_probability, 0, 1, "... whose mean marginal of their type is at least this"));
    f.push_back(SEMVOX_DOUBLE_FIELD("room_types", room_types, shape_weight, 0, 10,
                                    "weight of the room-shape evidence learnt from real plans (models/room_shape.json), 0 = off"));
    // ---- end room_types ----
    // render: viewpoints and virtual views (render/views.h).
    f.push_back(SEMVOX_INT_FIELD("render", render, width, 16, 8192, "view width, pixels"));
    f.push_back(SEMVOX_INT_FIELD("render", render, height, 16, 8192, "view height, pixels"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, horizontal_fov_deg, 2, 170, "horizontal field of view, degrees"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, height_fraction, 0.05, 0.95, "camera height between floor (0) and ceiling (1)"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, grid_spacing_m, 0.1, 100, "one viewpoint per square of this side, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, wall_clearance_m, 0, 10, "min distance from a viewpoint to a non-free voxel, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, yaw_step_deg, 1, 360, "yaw between views of a viewpoint, degrees; divides 360"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, pitch_deg, -89, 89, "camera pitch of the main ring, degrees (> 0 looks up)"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, tilted_ring_deg, 0, 89, "extra rings tilted down and up by this much (0: none), degrees"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, tilted_ring_yaw_step_deg, 1, 360, "yaw between views of the tilted rings, degrees; divides 360"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, max_depth_m, 0.01, 1e6, "hits deeper than this stay empty, metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, min_median_depth_m, 0, 100, "drop views with a smaller median depth (too close to a wall), metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, min_color_stddev, 0, 255, "drop views with a smaller colour spread (too homogeneous), 0-255"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, min_hit_fraction, 0, 1, "drop views where fewer pixels hit the scene"));
    f.push_back(SEMVOX_INT_FIELD("render", render, thumbnail_width, 16, 8192, "width of --save-views thumbnails, pixels"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, cloud_cell_m, 0, 1, "point clouds: points of each cube of this side are drawn as one disc at their centroid (0: one disc per point), metres"));
    f.push_back(SEMVOX_DOUBLE_FIELD("render", render, cloud_radius_factor, 1e-3, 10, "point clouds: disc radius as a multiple of the mean distance to the 8 nearest discs"));
    f.push_back(SEMVOX_BOOL_FIELD("render", render, cloud_squares, "point clouds: draw each disc as the square around it (two triangles, about 3 x faster to trace than a disc)"));
    // ---- semantic: classification views and the Voxel-CRF (apps/semantic_stage.h, voxelcrf/) ----
    f.push_back(SEMVOX_BOOL_FIELD("semantic", semantic, enabled, "run the per-view classifiers and the Voxel-CRF (voxels.ply, map.ot, semantic top view)"));
    f.push_back(SEMVOX_DOUBLE_FIELD("semantic", semantic, classify_yaw_step_deg, 1, 360, "yaw between candidate classification views of a viewpoint, degrees; divides 360"));
    {
      Field sel;
      sel.section = "semantic";
      sel.key = "view_selection";
      sel.doc = "classification views: cover (the fewest candidates that see each surface voxel min_views_per_voxel times, greedy set cover), all, all_objects_on_cover (every view classified, the support / clutter stage on the cover's views only), or auto (cover for meshes, all_objects_on_cover for point clouds)";
      sel.choices = {"auto", "cover", "all", "all_objects_on_cover"};
      sel.get_str = [](const PipelineConfig& c) { return std::string(ClassifyViewSelectionName(c.semantic.view_selection)); };
      sel.set_str = [](PipelineConfig& c, const std::string& v) { ParseClassifyViewSelection(v, &c.semantic.view_selection); };
      f.push_back(sel);
    }
    {
      Field m;
      m.section = "semantic";
      m.key = "voxel_crf_model";
      m.doc = "Voxel-CRF weights: mesh (models/voxel_crf.txt, trusts the per-view classifiers), cloud (models/voxel_crf_cloud.txt, learned on simulated fused clouds: the object segments count most), or auto (mesh for meshes with one flat colour per surface, as the generator makes them; cloud for point clouds and scanned, textured or uncoloured meshes)";
      m.choices = {"auto", "mesh", "cloud"};
      m.get_str = [](const PipelineConfig& c) { return std::string(VoxelCrfModelChoiceName(c.semantic.crf_model)); };
      m.set_str = [](PipelineConfig& c, const std::string& v) { ParseVoxelCrfModelChoice(v, &c.semantic.crf_model); };
      f.push_back(m);
    }
    f.push_back(SEMVOX_INT_FIELD("semantic", semantic.selection, min_views_per_voxel, 1, 100, "cover: chosen views that should see each surface voxel (k)"));
    f.push_back(SEMVOX_DOUBLE_FIELD("semantic", semantic.selection, max_incidence_deg, 1, 90, "cover: a view sees a voxel only when its ray meets the surface at most this far from the normal, degrees"));
    f.push_back(SEMVOX_DOUBLE_FIELD("semantic", semantic.selection, min_gain_fraction, 0, 0.999999, "cover: stop when the best further view meets less than this fraction of the total demand"));
    f.push_back(SEMVOX_INT_FIELD("semantic", semantic.selection, visibility_downscale, 1, 16, "cover: candidates are traced at 1/this of the classification resolution"));
    f.push_back(SEMVOX_INT_FIELD("semantic", semantic, classify_width, 16, 4096, "classification view width, pixels (the shipped classifiers are trained at 320)"));
    f.push_back(SEMVOX_INT_FIELD("semantic", semantic, classify_height, 16, 4096, "classification view height, pixels (trained at 240)"));
    f.push_back(SEMVOX_DOUBLE_FIELD("semantic", semantic.evidence, depth_sigma_voxels, 0.01, 100, "sigma of the depth term f_s, voxel sizes"));
    f.push_back(SEMVOX_DOUBLE_FIELD("semantic", semantic.evidence, completion_band_m, 0, 5, "unknown voxels this close to an occupied voxel can be completed, metres"));
    f.push_back(SEMVOX_INT_FIELD("semantic", semantic.evidence, interior_margin_cells, 0, 100, "columns this close to a free column count as inside, cells"));
    f.push_back(SEMVOX_INT_FIELD("semantic", semantic.evidence, ray_stride, 1, 64, "one classification ray per ray_stride x ray_stride pixels"));
    f.push_back(SEMVOX_DOUBLE_FIELD("semantic", semantic.evidence, ray_extension_m, 0, 10, "a ray's visible voxel may lie this far behind its observed hit, metres"));
    f.push_back(SEMVOX_INT_FIELD("semantic", semantic.crf, max_iterations, 1, 50, "Voxel-CRF iterations (Alg. 1) at most"));
    f.push_back(SEMVOX_DOUBLE_FIELD("semantic", semantic.crf, visibility_tolerance, 0, 1, "Alg. 1 stops once fewer than this fraction of rays change their visible voxel"));
    f.push_back(SEMVOX_DOUBLE_FIELD("semantic", semantic.crf, visibility_min_progress, 0, 1, "Alg. 1 also stops when an iteration moves more than (1 - this) times the rays the previous one moved"));
    f.push_back(SEMVOX_DOUBLE_FIELD("semantic", semantic.crf, plane_truncation, 0.001, 0.5, "Robust P^n truncation Q of plane cliques, fraction of the clique"));
    f.push_back(SEMVOX_DOUBLE_FIELD("semantic", semantic.crf, object_truncation, 0.001, 0.5, "Robust P^n truncation Q of object cliques, fraction of the clique"));
    f.push_back(SEMVOX_INT_FIELD("semantic", semantic.crf, min_object_voxels, 2, 1000000, "smallest object segment with a clique, voxels"));
    f.push_back(SEMVOX_BOOL_FIELD("semantic", semantic.crf, keep_scan_points, "point clouds: voxels holding an input point stay occupied (the Voxel-CRF labels them but does not empty them)"));
    f.push_back(SEMVOX_INT_FIELD("semantic", semantic.crf.planes, min_voxels, 3, 1000000, "smallest plane piece, voxels"));
    f.push_back(SEMVOX_DOUBLE_FIELD("semantic", semantic.crf.planes, normal_angle_deg, 0.1, 45, "plane detection: normal tolerance, degrees"));
    // ---- end semantic ----
    // ---- objects: support / clutter / other and generic object proposals (objects/support_stage.h) ----
    f.push_back(SEMVOX_BOOL_FIELD("objects", objects, enabled,
                                  "classify support / clutter / other in every classification view (needs semantic.enabled): support_clutter.ply, support_clutter_topview.png"));
    f.push_back(SEMVOX_BOOL_FIELD("objects", objects, proposals, "also generic object proposals, merged across views: object_proposals.json"));
    f.push_back(SEMVOX_BOOL_FIELD("objects", objects.classifier, use_crf, "dense pixel CRF on the SVM's superpixel probabilities (false: the SVM's output)"));
    f.push_back(SEMVOX_INT_FIELD("objects", objects.classifier.crf, iterations, 0, 100, "dense CRF mean-field iterations"));
    f.push_back(SEMVOX_DOUBLE_FIELD("objects", objects.fusion, min_label_probability, 0, 1, "a voxel is support / clutter only with at least this fused probability"));
    f.push_back(SEMVOX_DOUBLE_FIELD("objects", objects.proposal, min_score, 0, 1, "proposals scoring below this (the SVM's probability of an object) are dropped"));
    f.push_back(SEMVOX_DOUBLE_FIELD("objects", objects, merge_iou, 0.01, 1, "3D IoU at which proposals of different views merge"));
    // ---- end objects ----
    // ---- report: report.html (report/report.h) ----
    f.push_back(SEMVOX_BOOL_FIELD("report", report, view_3d,
                                  "interactive 3D view of voxels.ply in report.html (three.js inlined; `semvox report --no-3d` leaves it out)"));
    f.push_back(SEMVOX_INT_FIELD("report", report, view_3d_max_voxels, 1000, 10000000,
                                 "voxels in the 3D view at most (about 18 bytes each in the page); larger maps merge 2x2x2 blocks until they fit"));
    // ---- end report ----
    return f;
  }();
  return kFields;
}

std::string FormatNumber(double v, bool integer) {
  std::ostringstream os;
  if (integer) os << static_cast<long long>(v);
  else os << v;
  return os.str();
}

}  // namespace

Status ParseConfig(const std::string& yaml_text, const std::string& name, PipelineConfig* config) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    return Status::InvalidInput(FileError(name, std::string("invalid YAML: ") + e.what(), "check indentation and colons"));
  }
  if (root.IsNull()) return Status::Ok();
  if (!root.IsMap())
    return Status::InvalidInput(FileError(name, "the configuration must be a map of sections", "see `semvox config --dump`"));
  for (const auto& sec : root) {
    const std::string section = sec.first.as<std::string>("");
    bool section_known = false;
    for (const Field& f : Fields()) section_known |= f.section == section;
    if (!section_known)
      return Status::InvalidInput(FileError(name, "unknown section '" + section + "'", "see `semvox config --dump`"));
    if (!sec.second.IsMap())
      return Status::InvalidInput(FileError(name, "section '" + section + "' must be a map of key: value", ""));
    for (const auto& kv : sec.second) {
      const std::string key = kv.first.as<std::string>("");
      const Field* field = nullptr;
      for (const Field& f : Fields())
        if (f.section == section && f.key == key) field = &f;
      if (!field)
        return Status::InvalidInput(FileError(name, "unknown key '" + section + "." + key + "'", "see `semvox config --dump`"));
      const std::string full = section + "." + key;
      if (!kv.second.IsScalar())
        return Status::InvalidInput(FileError(name, full + " must be a single value", ""));
      const std::string text = kv.second.Scalar();
      if (!field->choices.empty()) {
        bool ok = false;
        std::string all;
        for (const auto& c : field->choices) ok |= c == text, all += (all.empty() ? "" : ", ") + c;
        if (!ok) return Status::InvalidInput(FileError(name, full + " = '" + text + "'. Allowed: " + all, ""));
        field->set_str(*config, text);
        continue;
      }
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0' || !std::isfinite(v))
        return Status::InvalidInput(FileError(name, full + " = '" + text + "' is not a number", ""));
      if (field->is_integer && v != std::floor(v))
        return Status::InvalidInput(FileError(name, full + " = " + text + " must be an integer", ""));
      if (v < field->min || v > field->max)
        return Status::InvalidInput(FileError(name, full + " = " + text + ". Allowed range: [" +
                                                        FormatNumber(field->min, field->is_integer) + ", " +
                                                        FormatNumber(field->max, field->is_integer) + "]", ""));
      field->set(*config, v);
    }
  }
  return CheckConfig(*config);
}

Status LoadConfigFile(const std::string& path, PipelineConfig* config) {
  std::string text;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &text));
  return ParseConfig(text, path, config);
}

Status CheckConfig(const PipelineConfig& config) {
  std::string error;
  if (!config.load.Check(&error)) return Status::InvalidInput("configuration: input." + error);
  if (!config.voxelize.Check(&error)) return Status::InvalidInput("configuration: mapping." + error);
  if (!config.occupancy.Check(&error)) return Status::InvalidInput("configuration: occupancy." + error);
  if (!config.floor_plan.Check(&error)) return Status::InvalidInput("configuration: rooms." + error);
  if (!config.rooms.Check(&error)) return Status::InvalidInput("configuration: rooms." + error);
  if (!config.room_types.Check(&error)) return Status::InvalidInput("configuration: room_types." + error);
  if (!config.render.Check(&error)) return Status::InvalidInput("configuration: render." + error);
  if (!config.semantic.Check(&error)) return Status::InvalidInput("configuration: semantic." + error);
  if (!config.objects.Check(&error)) return Status::InvalidInput("configuration: objects." + error);
  if (!config.report.Check(&error)) return Status::InvalidInput("configuration: report." + error);
  return Status::Ok();
}

std::string DumpConfig(const PipelineConfig& config) {
  std::ostringstream os;
  os << "# semvox configuration. Every key is optional; unknown keys are errors.\n";
  std::string section;
  for (const Field& f : Fields()) {
    if (f.section != section) {
      section = f.section;
      os << section << ":\n";
    }
    std::string value, range;
    if (!f.choices.empty()) {
      value = f.get_str(config);
      for (const auto& c : f.choices) range += (range.empty() ? "" : " | ") + c;
    } else {
      value = FormatNumber(f.get(config), f.is_integer);
      std::ostringstream r;  // A stream, not string concatenation: GCC 12 warns falsely (-Wrestrict) about the latter.
      r << "[" << FormatNumber(f.min, f.is_integer) << ", " << FormatNumber(f.max, f.is_integer) << "]";
      range = r.str();
    }
    os << "  " << f.key << ": " << value << "  # " << f.doc << "; " << range << "\n";
  }
  return os.str();
}

}  // namespace semvox
