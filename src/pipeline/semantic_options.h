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
  // After the rooms are typed, shower-curtain voxels in a room not typed bathroom become curtain: a shower
  // curtain's shape is a curtain's, only its room tells them apart (pipeline/room_types_stage.h).
  bool room_context = true;
  // The floor is a surface: floor voxels wholly above it (their bottom floor_surface_margin_m or more above the
  // floor) take the label of what stands above or beside them, after the Voxel-CRF (pipeline/semantic_solve.h).
  bool floor_surface = true;
  // Furniture stands on the floor: after the other steps, a floor voxel whose centre lies above the floor's surface
  // takes the label of the object voxel right above it (pipeline/semantic_solve.h, ApplyFurnitureFeet).
  bool furniture_feet = true;
  double floor_surface_margin_m = 0.03;
  // The walls' margin: wall voxels in the columns the object segmentation added to the walls (a cell around
  // every wall) take the label of at least wall_margin_min_neighbours of their neighbours that are neither wall,
  // floor nor ceiling, after the doors and windows (pipeline/semantic_solve.h).
  bool wall_margin = true;
  int wall_margin_min_neighbours = 2;
  // The walls' colour: wall voxels whose colour lies at least wall_colour_min_distance (RGB) from the walls'
  // median colour and closer to an object neighbour's take that neighbour's label, over wall_colour_rings rings,
  // after the walls' margin (pipeline/semantic_solve.h, ApplyWallColour).
  bool wall_colour = true;
  double wall_colour_min_distance = 40;
  int wall_colour_rings = 1;
  // A refrigerator is no wooden box: voxels labelled refrigerator whose neighbourhood's median colour is wood's
  // (hue 10-50 degrees) with a chroma (red - blue) of refrigerator_wood_chroma or more are a cabinet of its shape,
  // after the items (pipeline/semantic_solve.h, ApplyRefrigeratorColour). 0: off.
  int refrigerator_wood_chroma = 60;
  // A door's leaf stands in its doorway: after the doors and windows, the door voxels of an object segment far from
  // every door found take curtain (a thin panel) or cabinet (a tall box) (pipeline/semantic_solve.h,
  // ApplyDoorsInDoorways).
  bool doors_in_doorways = true;
  // Tall furniture is no wall: after the doors and windows, the wall voxels of an object segment whose top surface
  // lies 1.5 m or more above the floor and 0.3 m or more under the ceiling, and whose most probable class by shape
  // is an object (probability 0.5 or more), take that class (pipeline/semantic_solve.h, ApplyTallObjectWalls).
  bool tall_object_walls = true;
  // Wooden wall units are cabinets: after the tall objects, a hung part of the wall labels (bottom 1.0 m or more above
  // the floor, at most 1.3 m tall, 50 voxels or more) in wood's colour and another colour than the wall around it,
  // on no door's or window's span, is a cabinet (pipeline/semantic_solve.h, ApplyWoodenWallUnits).
  bool wooden_wall_units = true;
  // A wall stands on the floor; a wall cabinet hangs: after the wooden wall units, a part of the wall labels over
  // 0.4 m of free space, its bottom 1.0-1.8 m above the floor, at most 1.3 m tall, 50 voxels or more, on no door's
  // or window's span, is a cabinet (pipeline/semantic_solve.h, ApplyHungWallCabinets).
  bool hung_wall_cabinets = true;
  // A bar is a table by name and a counter by use: after the room types, the counter voxels of an object segment
  // whose top surface lies 1.0 m or more above the floor and whose footprint's centre lies 0.6 m or more from every
  // wall take table (pipeline/semantic_solve.h, ApplyBarTables).
  bool bar_tables = true;
  // A counter is a work surface at counter height: an object segment whose top surface lies lower than this
  // (metres above the floor) is no counter, and the segment classifier's counter probability goes to table
  // before the Voxel-CRF (objects/segment_classifier.h, LowCounterToTable). 0: off.
  double counter_min_top_m = 0.75;
  // A sofa's back beside its seat: an object segment the shape classifier calls bed that touches a segment it
  // calls sofa (probability >= 0.9) and whose top surface lies more than 0.15 m above that seat's gives its bed
  // probability to sofa before the Voxel-CRF (objects/segment_classifier.h, SofaBacksBesideSeats).
  bool sofa_backs = true;
  // What stands how high: an object segment whose top surface lies above every chair's, sofa's, bed's, table's,
  // desk's, counter's or sink's of the world gives those classes' probability to the others before the
  // Voxel-CRF (objects/segment_classifier.h, HighTopsToOtherClasses; the limits in pipeline/semantic_evidence.cc).
  bool high_tops = true;
  // Views unlike the training views say less about their room: a view whose room-type descriptor lies beyond the
  // training views' familiar distance has its room-type distribution mixed with the uniform one, fully at twice
  // that distance (perception/room_evidence.h, DiscountUnfamiliarRoomView).
  bool room_view_familiarity = true;
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
            OptionSwitch(&O::room_context, "room_context",
                         "after the room types, shower-curtain voxels in a room not typed bathroom become curtain "
                         "(the two differ by their room, not their shape); off: the Voxel-CRF's label stays"),
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
            OptionSwitch(&O::wall_margin, "wall_margin",
                         "after the doors and windows, wall voxels in the cell the object segmentation adds around every "
                         "wall (the back of a sofa, a toilet or a door frame standing against it) take the label most of "
                         "their neighbours that are not wall, floor or ceiling carry; off: the Voxel-CRF's label stays"),
            OptionNumber(&O::wall_margin_min_neighbours, "wall_margin_min_neighbours", 1, 26, "voxels",
                         "how many of a margin voxel's 26 neighbours must carry that label for wall_margin"),
            OptionSwitch(&O::wall_colour, "wall_colour",
                         "after the walls' margin, a voxel labelled wall whose colour lies wall_colour_min_distance or "
                         "more from the walls' median colour, and closer to that of a neighbour labelled as an object, "
                         "takes that neighbour's label (a wooden wardrobe's front, a window's frame, a toilet's back "
                         "in the wall band); off: the label stays wall"),
            OptionNumber(&O::wall_colour_min_distance, "wall_colour_min_distance", 0, 442, "RGB units",
                         "how far (Euclidean, 0-255 per channel) a wall voxel's colour must lie from the walls' median "
                         "colour for wall_colour"),
            OptionNumber(&O::wall_colour_rings, "wall_colour_rings", 0, 20, "voxels",
                         "how many voxels deep an object's colour spreads into the wall band for wall_colour"),
            OptionNumber(&O::refrigerator_wood_chroma, "refrigerator_wood_chroma", 0, 255, "RGB units",
                         "after the items, a voxel labelled refrigerator whose colour (the median over it and its "
                         "neighbours labelled refrigerator) is wood's, red >= green >= blue with a hue of 10-50 degrees "
                         "and a chroma (red - blue) of this or more, is a cabinet of its shape (a wooden pantry unit, "
                         "tall cabinet or the cabinet over the refrigerator): refrigerators are no wooden boxes; 0: off"),
            OptionSwitch(&O::doors_in_doorways, "doors_in_doorways",
                         "after the doors and windows, when doors were found in the walls, the voxels labelled door of an "
                         "object segment that lie farther from every door found than its width + 0.3 m are no leaf: a "
                         "segment up to 0.35 m thick (a panel hung along a wall) takes curtain, a thicker one (a tall "
                         "box) cabinet; off: the labels stay"),
            OptionSwitch(&O::tall_object_walls, "tall_object_walls",
                         "after the doors and windows, the voxels labelled wall of an object segment whose top surface "
                         "lies 1.5 m or more above the floor and 0.3 m or more under the ceiling (or the scan's top), and "
                         "whose most probable class by shape is an object with a probability of 0.5 or more, take that "
                         "class: a wardrobe's or tall cabinet's front is no wall; off: the labels stay"),
            OptionSwitch(&O::wooden_wall_units, "wooden_wall_units",
                         "after the tall objects, a part of the voxels labelled wall in wood's colour (hue 10-50 degrees, "
                         "chroma 60 or more) that hangs on the wall (its bottom 1.0 m or more above the floor, at most "
                         "1.3 m tall, 50 voxels or more), lies on no door's or window's span and differs from the wall "
                         "around it by 30 or more (RGB) is a cabinet: wooden wall units; off: the labels stay"),
            OptionSwitch(&O::hung_wall_cabinets, "hung_wall_cabinets",
                         "after the wooden wall units, a part of the voxels labelled wall that hangs over 0.4 m of free "
                         "space (its bottom 1.0-1.8 m above the floor, at most 1.3 m tall, 50 voxels or more) and lies on "
                         "no door's or window's span is a cabinet: a wall stands on the floor, a wall cabinet hangs; "
                         "off: the labels stay"),
            OptionSwitch(&O::bar_tables, "bar_tables",
                         "after the room types (which read it as kitchen furniture), the voxels labelled counter of an "
                         "object segment whose top surface lies 1.0 m or more above the floor and whose footprint's "
                         "centre lies 0.6 m or more from every wall take table: a bar or island, which ScanNet and NYU "
                         "name table; off: the labels stay"),
            OptionNumber(&O::counter_min_top_m, "counter_min_top_m", 0, 3, "metres",
                         "an object segment whose top surface lies lower than this above the floor is no counter: the "
                         "segment classifier's counter probability goes to table before the Voxel-CRF (kitchen counters "
                         "stand 0.85-0.95 m, bathroom vanities from about 0.76 m); 0: off"),
            OptionSwitch(&O::sofa_backs, "sofa_backs",
                         "before the Voxel-CRF, an object segment the shape classifier calls bed that touches a segment it "
                         "calls sofa (probability 0.9 or more) and stands more than 0.15 m higher is that sofa's back and "
                         "arms: its bed probability goes to sofa; off: the classifier's probabilities stay"),
            OptionSwitch(&O::high_tops, "high_tops",
                         "before the Voxel-CRF, an object segment whose top surface stands higher than any chair's or "
                         "sofa's (1.2 m), table's, desk's, counter's or sink's (1.4 m) or bed's (1.6 m) is none of them: "
                         "their probability goes to the other classes; off: the classifier's probabilities stay"),
            OptionSwitch(&O::room_view_familiarity, "room_view_familiarity",
                         "a view whose room-type descriptor lies farther from the training views than they lie from "
                         "each other (their 0.99-quantile) says less about its room: its room-type distribution mixes "
                         "with the uniform one, in proportion up to twice that distance, where it says nothing; off: "
                         "every view counts fully"),
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
