// Sub-commands of the semvox binary. main.cc parses the command line (CLI11) and calls these.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "apps/config.h"
#include "core/status.h"
#include "pipeline/onnx_stage.h"

namespace semvox {

struct OnnxModels;  // pipeline/onnx_stage.h

struct RunArgs {
  std::string input;
  std::string outdir;
  std::string config_path;     // Optional YAML file.
  std::string up;              // "", "auto", "z" or "y" (overrides the config when set).
  double scale = 0;            // > 0 overrides the config.
  bool json = false;           // Print summary.json on stdout.
  long long max_voxels = 0;    // > 0 overrides mapping.max_voxels.
  bool save_views = false;     // Also write PNG thumbnails of every view into OUTDIR/views/.
  double min_confidence = -1;  // In [0, 1]: overrides semantic.min_confidence.
  std::string models_dir;      // Model files; empty: $SEMVOX_MODELS, else beside the binary (apps/models_dir.h).
  std::string argv0;           // The binary's argv[0]: finds the models when /proc/self/exe cannot be read.
  // Optional ONNX backend (pipeline/onnx_stage.h): networks, label maps and input sizes.
  OnnxModelPaths onnx_paths;
  std::shared_ptr<const OnnxModels> onnx;  // Loaded by main.cc before RunRunCommand; null without ONNX flags.
};

// `semvox run`: the pipeline (pipeline/pipeline.h) on args.input; its outputs, config_used.yaml and report.html
// in args.outdir.
Status RunRunCommand(const RunArgs& args);

struct GenerateArgs {
  std::string outdir;
  bool demo = false;  // The bundled demo apartment instead of a random one.
  int seed = 0;
  bool cloud = false;  // Also simulate a scanner and write cloud.ply.
  bool clean = false;  // No scan artefacts in mesh.ply.
  bool randomised = false;  // Also write scan.ply: the apartment scanned as the randomised training style does.
  std::string plan;    // An R2V floor plan (plan_*.txt) to build the apartment on instead of a drawn layout.
  bool no_furniture = false;  // With --plan: only the plan's fixtures (no furniture by room type, no props).
  std::vector<std::string> settings;  // "apartment.NAME=V", "artefacts.NAME=V", "scan.NAME=V" overrides.
};

// `semvox generate`: writes a labelled apartment (mesh.ply, ...) into OUTDIR.
Status RunGenerate(const GenerateArgs& args);

struct EvalArgs {
  std::string pred_dir;    // OUTDIR of `semvox run`.
  std::string gt_dir;      // Directory written by `semvox generate --seed N`.
  std::string boxes_path;  // Or: a real scan's furniture boxes (gt.json with axis_align_matrix; eval/box_eval.h).
  std::string points_path; // Or: a real scan's labelled points (PLY with x, y, z, label; eval/point_eval.h).
  std::string output;      // JSON report path; default PRED/eval.json with --gt, none with --boxes.
  bool json = false;       // Print the JSON report on stdout instead of the table.
};

// `semvox eval`: scores the run's outputs against the ground truth (--gt: a generated apartment, writes
// eval.json; --boxes: a real scan's furniture boxes, eval/box_eval.h; --points: its labelled points,
// eval/point_eval.h), prints a table or the JSON report.
Status RunEval(const EvalArgs& args);

// ---- rooms (apps/rooms_command.cc) ----
struct RoomsArgs {
  std::string map_path;           // 2D map image: 0 occupied, 255 free.
  double resolution_m = 0.05;     // Metres per pixel.
  std::string method;             // "" = the configuration's rooms.method.
  std::string outdir;
  std::string config_path;        // Optional YAML file; its rooms section applies.
  std::string ground_truth_path;  // Optional ipa-style _gt_segmentation.png: print recall and precision.
};

// `semvox rooms`: segments a 2D map into rooms; writes OUTDIR/rooms.png (16-bit ids), rooms.geojson, rooms.svg,
// config_used.yaml.
Status RunRooms(const RoomsArgs& args);

// ---- render (apps/render_command.cc) ----
struct RenderArgs {
  std::string input;
  std::string outdir;
  std::string config_path;         // Optional YAML file; its render section sets size and field of view.
  std::string up;                  // As for RunArgs.
  double scale = 0;
  std::vector<std::string> poses;  // "x,y,z,yaw_deg[,pitch_deg]" each, world frame, metres and degrees.
  double horizontal_fov_deg = 0;   // > 0 overrides render.horizontal_fov_deg.
  int width = 0, height = 0;       // > 0 override render.width / render.height.
  double voxel_size_m = 0;         // > 0 overrides mapping.voxel_size_m (resolution of the voxel keys).
};

// `semvox render`: renders the given poses into OUTDIR as view_NN_{rgb,depth,normal,keys}.png plus
// views.json (poses, intrinsics, per-view statistics).
Status RunRender(const RenderArgs& args);

// ---- batch (apps/batch_command.cc) ----
struct BatchArgs {
  std::string manifest;     // One scan per line: INPUT, or NAME INPUT; '#' starts a comment.
  std::string root;         // ROOT/<name>/ per scan, ROOT/index.{csv,json}, ROOT/logs/.
  std::string config_path;  // Passed to every `semvox run`.
  int jobs = 1;             // Scans run at once.
};

// `semvox batch`: resumable, keeps going past failures; kInternal (exit 1) when any scan failed.
Status RunBatch(const BatchArgs& args);

// ---- train (apps/train_command.cc) ----
struct TrainArgs {
  std::string outdir = "models";            // Model files and train_report.json.
  std::string train_seeds = "0-39";         // Generator seeds to train on ("A-B" or "A,B,...").
  std::string val_seeds = "100-109";        // Generator seeds to score on.
  int max_rows = 20000;                     // Rows kept per k-NN model (even stride), 0 = all.
  int crf_holdout = 5;                      // Last training seeds kept out of the k-NN for CRF weight learning.
  bool voxel_crf_only = false;              // Train only the Voxel-CRF (needs the per-view models in outdir).
  bool segments_only = false;               // Train only the object-segment classifier.
  bool room_type_evidence_only = false;     // Relearn only the room-type CRF's evidence terms on R2V plan apartments.
  std::string room_type_evidence_seeds = "40-79";  // ... and on these generated apartments (neither the classifiers' nor validation).
  std::string room_type_calibration_plans = "250-299";  // ... choosing the weights' scale on these R2V training plans (held out; "" = on the learning scenes).
  int room_type_ssvm_runs = 3;              // ... averaging the SSVM direction over this many runs.
  bool room_shapes_only = false;            // Train only the room-shape model (real R2V plans).
  std::string room_shape_features;          // Its features, comma-separated names (empty: the default set).
  bool room_type_statistics_only = false;   // Recompute the R2V fixture statistics of OUTDIR/room_type_crf.json.
  bool room_type_knn_only = false;          // Rebuild OUTDIR/room_type_knn.bin from generated apartments + R2V plans.
  int room_type_plans = 300;                // ... from the first this many sorted R2V plans (<= 300, the training split).
  int view_plans = 0;                       // `semvox train`: apartments built on the first N sorted R2V training plans add
                                            // rows to the per-view classifiers (nyu4.*, second.*).
  std::string room_type_knn_classes = "truth";  // ... descriptors of the views' true or predicted (OUTDIR/second.*) classes.
  std::string r2v_dir;                      // R2V plans (empty: ../shared/data/r2v from the working directory).
  std::string segment_seeds = "0-99";       // Generator seeds the object-segment classifier learns on (randomised scans).
  std::string segment_classifier = "knn";   // knn (object_segments.knn) or forest (object_segments.forest).
  std::string voxel_crf_seeds = "0-7";      // Generator seeds the Voxel-CRF weights are learned on.
  int voxel_crf_epochs = 12;                // Structural-SVM epochs.
  // Scans the Voxel-CRF weights learn on: flat (the generator's meshes; the default since 2026-12-05, because
  // `semvox run` gives voxel_crf.txt only to meshes coloured as the generator colours them), randomised (the
  // training scans of the real-scans work: palettes, textures, simulated clouds), mixed (alternating, first
  // flat) or cloud (simulated fused clouds, written to voxel_crf_cloud.txt).
  std::string voxel_crf_style = "flat";
  // When >= 0, w_appearance (the per-view evidence) is held at this value instead of learned: the weight
  // the flat-trained model gives it, so that clean meshes keep their labels while the other weights (the
  // segment term among them) learn on mixed scans.
  double voxel_crf_appearance_weight = -1;
  std::string style = "flat";               // Training views: flat (the shipped models) or randomised (domain randomisation).
};

// `semvox train`: per-view classifiers (k-NN unaries, tree and union CRFs) from generated apartments.
Status RunTrain(const TrainArgs& args);
// `semvox train --voxel-crf`: the Voxel-CRF's weights (structural SVM) and layout prior -> OUTDIR/voxel_crf.txt
// (pipeline/voxel_crf_training.h).
Status RunTrainVoxelCrf(const TrainArgs& args);

// `semvox train --segments`: only models/object_segments.knn or .forest (and object_segments_report.json).
Status RunTrainSegments(const TrainArgs& args);
// `semvox train --room-shapes`: only models/room_shape.json (and room_shape_report.json), from R2V plans
// 0-299; plans 300-399 validate.
Status RunTrainRoomShapes(const TrainArgs& args);
// `semvox train --room-type-statistics`: OUTDIR/room_type_crf.json's R2V fixture statistics (counter, sink,
// toilet, bathtub given the room type) recomputed from the training seeds' apartments and R2V plans 0-299;
// its learned terms stay.
Status RunTrainRoomTypeStatistics(const TrainArgs& args);
// `semvox train --room-type-knn`: OUTDIR/room_type_knn.bin, the per-view room-type k-NN, from the ground-truth
// classes of the training views of the --train-seeds apartments (as `semvox train` builds it) and of apartments
// built on the first --room-type-plans sorted R2V plans (real layouts, furnished by room type).
Status RunTrainRoomTypeKnn(const TrainArgs& args);
// `semvox train --room-type-evidence`: OUTDIR/room_type_crf.json's learned evidence terms (the confusion of Eq. 3,
// the SSVM weights of every variant, the dense-CRF parameters) relearned on apartments built on the first
// --room-type-plans sorted R2V training plans and on the generated apartments --room-type-evidence-seeds, their
// training views classified by OUTDIR/second.* and typed by OUTDIR/room_type_knn.bin; its statistics stay.
Status RunTrainRoomTypeEvidence(const TrainArgs& args);
// "A-B" or "A,B,..." -> seeds.
Status ParseSeedList(const std::string& text, const char* flag, std::vector<uint64_t>* seeds);

// ---- report and labels (apps/report_command.cc, apps/labels_command.cc) ----
struct ReportArgs {
  std::string outdir;       // OUTDIR of a `semvox run`.
  std::string config_path;  // Optional YAML file; its report section applies.
  bool no_3d = false;       // Leave the 3D view out (overrides report.view_3d).
};
// `semvox report`: (re)writes OUTDIR/report.html (src/report/report.h).
Status RunReport(const ReportArgs& args);
// `semvox labels`: NYU40 classes with their Eigen-13 and NYU-4 classes, and the room types, as Markdown.
std::string LabelsMarkdown();
Status RunLabels();

// ---- remove (apps/remove_command.cc; src/pipeline/object_removal_stage.h) ----
struct RemoveArgs {
  std::string outdir;                // OUTDIR of a `semvox run` (voxels.ply, map.ot, summary.json).
  std::string output;                // OUT2: where the edited map goes (must differ from OUTDIR).
  std::vector<std::string> classes;  // NYU40 names (or ids) to remove.
  std::vector<int> instances;        // Instance ids (`semvox remove OUTDIR --list`).
  bool all_furniture = false;        // Every NYU-4 furniture and props voxel.
  bool list = false;                 // Print the instances and exit.
};
// `semvox remove`: removes objects and completes the space behind them (Voxel-CRF paper, Sec. 6.4).
Status RunRemove(const RemoveArgs& args);

}  // namespace semvox
