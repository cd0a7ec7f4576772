// Options of the semantic stage of the pipeline (pipeline/pipeline.h): which classification views are
// classified, which Voxel-CRF weights are used, and the options of view selection, evidence and the CRF.
#pragma once
#include <string>
#include <vector>

#include "core/option_table.h"
#include "core/geometry.h"
#include "render/view_selection.h"
#include "voxelcrf/voxel_crf.h"
#include "voxelcrf/voxel_evidence.h"

namespace semvox {

struct LabelLevel;  // perception/label_levels.h

// Which candidate classification views are classified.
enum class ClassifyViewSelection {
  kAll,    // Every candidate that passes the classifier's filters.
  kCover,  // The greedy multi-cover of the surface voxels (render/view_selection.h).
  kAllObjectsOnCover,  // Every candidate is classified (labels and room-type evidence), but only the cover's
                       // views go to the view hook (the support / clutter stage).
  kAuto,   // kCover for every input (resolved by `semvox run` once the input is loaded). Point clouds used to
           // classify every view for their room-type evidence; since the room-shape evidence and the cloud
           // Voxel-CRF weights (which give the per-view evidence almost no weight), the cover keeps the
           // randomised clouds' labels and room types within 0.2 points and the studio's box scores.
};
const char* ClassifyViewSelectionName(ClassifyViewSelection s);  // "all", "cover", "all_objects_on_cover", "auto"
bool ParseClassifyViewSelection(const std::string& name, ClassifyViewSelection* s);
// `s`, with kAuto resolved for `scene` (kCover for meshes and point clouds).
ClassifyViewSelection ResolveViewSelection(ClassifyViewSelection s, const Scene& scene);

// Which Voxel-CRF weights are used.
enum class VoxelCrfModelChoice {
  kMesh,   // models/voxel_crf.txt: trusts the per-view evidence, which is reliable only on what the per-view
           // classifiers learned from: meshes with one flat colour per surface (the generator's style).
  kCloud,  // models/voxel_crf_cloud.txt: learned on simulated fused clouds (`--voxel-crf-style cloud`); the
           // per-view evidence gets almost no weight, the object segments count most. Falls back to
           // voxel_crf.txt with a warning when absent.
  kAuto,   // kMesh for flat-coloured meshes (FlatColouredMesh), kCloud for point clouds and every other mesh
           // (textured, colour per vertex as scanned, or no colour); resolved by `semvox run`.
};
const char* VoxelCrfModelChoiceName(VoxelCrfModelChoice c);  // "mesh", "cloud", "auto"
bool ParseVoxelCrfModelChoice(const std::string& name, VoxelCrfModelChoice* c);

// A mesh coloured like the generator's: vertex colours, no texture, and at least half the faces with one
// colour on all three vertices. A scanned mesh's colours vary from vertex to vertex; a textured or
// uncoloured mesh gives the per-view classifiers no flat colours either.
bool FlatColouredMesh(const Mesh& mesh);

struct SemanticStageOptions {
  bool enabled = true;
  double classify_yaw_step_deg = 30.0;
  // The shipped classifiers were trained on 320 x 240 views (the SLIC superpixel size and the dense CRF's
  // kernel widths are in pixels), so other sizes trade labels for speed.
  int classify_width = 320;
  int classify_height = 240;
  ClassifyViewSelection view_selection = ClassifyViewSelection::kAuto;
  VoxelCrfModelChoice crf_model = VoxelCrfModelChoice::kAuto;
  // Doors and windows found in the walls by their shape (objects/wall_openings.h) relabel the wall voxels
  // of their pane or closed leaf, and their open leaf, after the Voxel-CRF.
  bool wall_openings = true;
  // The voxels of an object segment that came out "other" get one NYU40 id (pillow, box, lamp, ...) from
  // their shape (objects/other_labels.h, models/other_labels.knn), after the Voxel-CRF.
  bool other_labels = true;
  // What lies on furniture (its voxels above the segment's top surface: a pillow on a bed, books on a table,
  // a sink on a counter) gets its own NYU40 id when its shape says it is an object of its own
  // (objects/other_labels.h, models/item_labels.knn), after the "other" labels.
  bool item_labels = true;
  // The floor is a surface: floor voxels wholly above it (their bottom floor_surface_margin_m or more above the
  // floor) take the label of what stands above or beside them, after the Voxel-CRF (pipeline/semantic_solve.h).
  bool floor_surface = true;
  // Furniture stands on the floor: after the other steps, a floor voxel whose centre lies above the floor's surface
  // takes the label of the object voxel right above it (pipeline/semantic_solve.h, ApplyFurnitureFeet).
  bool furniture_feet = true;
  double floor_surface_margin_m = 0.03;
  // A bar is a table by name and a counter by use: after the room types, the counter voxels of an object segment
  // whose top surface lies 1.0 m or more above the floor and whose footprint's centre lies 0.6 m or more from every
  // wall take table (pipeline/semantic_solve.h, ApplyBarTables).
  bool bar_tables = true;
  // A counter is a work surface at counter height: an object segment whose top surface lies lower than this
  // (metres above the floor) is no counter, and the segment classifier's counter probability goes to table
  // before the Voxel-CRF (objects/segment_classifier.h, LowCounterToTable). 0: off.
  double counter_min_top_m = 0.75;
  // Views unlike the training views say less about their room: a view whose room-type descriptor lies beyond the
  // training views' familiar distance has its room-type distribution mixed with the uniform one, fully at twice
  // that distance (perception/room_evidence.h, DiscountUnfamiliarRoomView).
  bool room_view_familiarity = true;
  // Labels whose confidence lies under this are written as 0 (unlabelled) to map.ot and the semantic top views;
  // voxels.ply keeps every voxel's best guess with its confidence (pipeline/semantic_exports.h). 0: every label.
  double min_confidence = 0;
  ViewSelectionOptions selection;  // For kCover.
  VoxelEvidenceOptions evidence;
  VoxelCrfOptions crf;

  // The fields users set (section `semantic`, with those of selection, evidence and crf): meaning, unit and range.
  static const OptionTable<SemanticStageOptions>& Options() {
    using O = SemanticStageOptions;
    static const OptionTable<O> table = JoinOptions<O>({
        {
            OptionSwitch(&O::enabled, "enabled",
                         "run the per-view classifiers and the Voxel-CRF (voxels.ply, map.ot, semantic top view)"),
            OptionNumber(&O::classify_yaw_step_deg, "classify_yaw_step_deg", 1, 360, "degrees",
                         "yaw between candidate classification views of a viewpoint (divides 360)"),
            OptionChoice(&O::view_selection, "view_selection", {"auto", "cover", "all", "all_objects_on_cover"},
                         ParseClassifyViewSelection,
                         "classification views: cover (the fewest candidates that see each surface voxel "
                         "min_views_per_voxel times, greedy set cover), all, all_objects_on_cover (every view "
                         "classified, the support / clutter stage on the cover's views only), or auto (cover)"),
            OptionChoice(&O::crf_model, "voxel_crf_model", {"auto", "mesh", "cloud"}, ParseVoxelCrfModelChoice,
                         "Voxel-CRF weights: mesh (models/voxel_crf.txt, trusts the per-view classifiers), cloud "
                         "(models/voxel_crf_cloud.txt, learned on simulated fused clouds: the object segments count "
                         "most), or auto (mesh for meshes with one flat colour per surface, as the generator makes "
                         "them; cloud for point clouds and scanned, textured or uncoloured meshes)"),
        },
        NestedOptions(&O::selection, ViewSelectionOptions::Options()),
        {
            OptionSwitch(&O::wall_openings, "wall_openings",
                         "after the Voxel-CRF, doors and windows found in the walls by their shape (a rectangle "
                         "recessed or open in a wall, framed by it) relabel the wall voxels of their pane or leaf"),
            OptionSwitch(&O::other_labels, "other_labels",
                         "after the Voxel-CRF, the voxels of an object segment labelled \"other\" get the NYU40 "
                         "id their shape says (pillow, box, bag, lamp, television, night stand, ...; "
                         "models/other_labels.knn); off: every \"other\" voxel gets the one id the CRF model names"),
            OptionSwitch(&O::item_labels, "item_labels",
                         "after the Voxel-CRF, what lies on an object segment above its top surface (a pillow on a bed, "
                         "books on a table, a sink on a counter) gets its own NYU40 id when its shape says it is an "
                         "object of its own (models/item_labels.knn); off: it keeps the furniture's label"),
            OptionSwitch(&O::floor_surface, "floor_surface",
                         "after the Voxel-CRF, floor voxels lying wholly above the floor's surface (the bottoms of walls "
                         "and furniture) take the label of the voxel above them or of most of their neighbours; off: "
                         "the Voxel-CRF's label stays"),
            OptionSwitch(&O::furniture_feet, "furniture_feet",
                         "after the other steps, a voxel labelled floor whose centre lies above the floor's surface and "
                         "whose upper neighbour is labelled an object (not floor, ceiling, wall, door or window) takes that "
                         "label: the foot of the furniture standing there; off: the labels stay"),
            OptionNumber(&O::floor_surface_margin_m, "floor_surface_margin_m", 0, 0.5, "metres",
                         "how far above the floor a voxel's bottom must lie for floor_surface (the floor's scan noise)"),
            OptionSwitch(&O::bar_tables, "bar_tables",
                         "after the room types (which read it as kitchen furniture), the voxels labelled counter of an "
                         "object segment whose top surface lies 1.0 m or more above the floor and whose footprint's "
                         "centre lies 0.6 m or more from every wall take table: a bar or island, which ScanNet and NYU "
                         "name table; off: the labels stay"),
            OptionNumber(&O::counter_min_top_m, "counter_min_top_m", 0, 3, "metres",
                         "an object segment whose top surface lies lower than this above the floor is no counter: the "
                         "segment classifier's counter probability goes to table before the Voxel-CRF (kitchen counters "
                         "stand 0.85-0.95 m, bathroom vanities from about 0.76 m); 0: off"),
            OptionSwitch(&O::room_view_familiarity, "room_view_familiarity",
                         "a view whose room-type descriptor lies farther from the training views than they lie from "
                         "each other (their 0.99-quantile) says less about its room: its room-type distribution mixes "
                         "with the uniform one, in proportion up to twice that distance, where it says nothing; off: "
                         "every view counts fully"),
            OptionNumber(&O::min_confidence, "min_confidence", 0, 1, "",
                         "labels whose confidence lies under this are written as 0 (unlabelled) to map.ot and the semantic "
                         "top views (drawn dark grey); voxels.ply keeps every voxel's best guess with its confidence; 0: "
                         "every label (`semvox run --min-confidence`)"),
            OptionNumber(&O::classify_width, "classify_width", 16, 4096, "pixels",
                         "classification view width (the shipped classifiers are trained at 320)"),
            OptionNumber(&O::classify_height, "classify_height", 16, 4096, "pixels",
                         "classification view height (trained at 240)"),
        },
        NestedOptions(&O::evidence, VoxelEvidenceOptions::Options()),
        NestedOptions(&O::crf, VoxelCrfOptions::Options()),
    });
    return table;
  }
  bool Check(std::string* error) const;
};

// The NYU40 id written for each class of `level` ("other" -> otherprop), before training picks better.
std::vector<int> Nyu40OfClasses(const LabelLevel& level);

}  // namespace semvox
