// The semvox command-line tool: one binary with sub-commands.
#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdio>
#include <iostream>
#include <unistd.h>

#include "apps/commands.h"
#include "apps/config.h"
#include "pipeline/onnx_stage.h"
#include "core/file_util.h"
#include "core/log.h"

namespace {

void OnSignal(int sig) {
  semvox::RemovePendingTemporaries();
  const char msg[] = "semvox: interrupted; no partial outputs were left\n";
  ssize_t ignored = ::write(2, msg, sizeof(msg) - 1);
  (void)ignored;
  _exit(128 + sig);
}

int Report(const semvox::Status& st) {
  if (st.ok()) return 0;
  std::fprintf(stderr, "semvox: error: %s\n", st.message().c_str());
  return st.exit_code();
}

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);

  CLI::App app{"semvox: scanned apartment -> labelled 3D voxel map with rooms"};
  app.require_subcommand(1);
  bool quiet = false, verbose = false;
  app.add_flag("-q,--quiet", quiet, "print warnings and errors only");
  app.add_flag("-v,--verbose", verbose, "also print each step's detail (the default of every command but run and batch)");

  semvox::RunArgs run;
  run.argv0 = argc > 0 && argv[0] ? argv[0] : "";
  CLI::App* run_cmd = app.add_subcommand("run", "map a mesh or point cloud into OUTDIR");
  run_cmd->add_option("input", run.input, "mesh (.ply .obj .gltf .glb .off .stl) or cloud (.ply .pcd .txt .xyz)")->required();
  run_cmd->add_option("-o,--output", run.outdir, "output directory")->required();
  run_cmd->add_option("--config", run.config_path, "YAML configuration (see `semvox config --dump`)");
  run_cmd->add_option("--up", run.up, "up axis of the input: auto, z, y, -y (a camera's frame, y down), x, -x, -z; write --up=-y")
      ->check(CLI::IsMember({"auto", "z", "y", "-y", "x", "-x", "-z", "+z", "+y", "+x"}));
  run_cmd->add_option("--scale", run.scale, "multiply coordinates into metres (0.001 for mm)")->check(CLI::PositiveNumber);
  run_cmd->add_flag("--json", run.json, "print summary.json on stdout");
  run_cmd->add_option("--max-voxels", run.max_voxels, "refuse voxel grids larger than this (memory guard)")
      ->check(CLI::PositiveNumber);
  run_cmd->add_flag("--save-views", run.save_views, "write PNG thumbnails of every view into OUTDIR/views/");
  run_cmd->add_option("--min-confidence", run.min_confidence,
                      "labels under this confidence are written as 0 (unlabelled) to map.ot and the semantic top views; "
                      "voxels.ply keeps them all (semantic.min_confidence)")
      ->check(CLI::Range(0.0, 1.0));
  // Optional ONNX backend (pipeline/onnx_stage.h, docs/perception.md).
  run_cmd->add_option("--scene-model", run.onnx_paths.scene_model, "Places365-style scene network (.onnx) for the room-type evidence");
  run_cmd->add_option("--scene-labels", run.onnx_paths.scene_labels, "label map of --scene-model: NET_INDEX ROOM_TYPE lines");
  run_cmd->add_option("--scene-input", run.onnx_paths.scene_input_size, "input size of --scene-model, WxH (default 224x224)");
  run_cmd->add_option("--object-model", run.onnx_paths.object_model, "segmentation network (.onnx) for the per-pixel class probabilities");
  run_cmd->add_option("--object-labels", run.onnx_paths.object_labels, "label map of --object-model: NET_INDEX NYU40_CLASS lines");
  run_cmd->add_option("--object-input", run.onnx_paths.object_input_size, "input size of --object-model, WxH (default 224x224)");
  run_cmd->add_option("--models", run.models_dir, "directory of the model files (default: $SEMVOX_MODELS, else ../share/semvox/models "
                      "relative to the semvox binary, where `cmake --install` puts them)");
  run_cmd->add_flag("-q,--quiet", quiet, "print warnings and errors only");
  run_cmd->add_flag("-v,--verbose", verbose, "also print each step's detail (counts, models, timings)");

  semvox::GenerateArgs gen;
  CLI::App* gen_cmd = app.add_subcommand("generate", "write a labelled synthetic apartment into OUTDIR");
  gen_cmd->add_option("-o,--output", gen.outdir, "output directory")->required();
  gen_cmd->add_flag("--demo", gen.demo, "the bundled demo apartment");
  gen_cmd->add_option("--seed", gen.seed, "random seed");
  gen_cmd->add_flag("--cloud", gen.cloud, "also simulate a scanner walk and write cloud.ply");
  gen_cmd->add_flag("--clean", gen.clean, "no scan artefacts in mesh.ply");
  gen_cmd->add_flag("--randomised", gen.randomised, "also write scan.ply: the apartment scanned in the randomised style (palette colours, textures, lighting; a fused cloud of random spacing or a mesh with random artefacts)");
  gen_cmd->add_option("--plan", gen.plan, "build the apartment on a real floor plan in the R2V format (plan_*.txt of ../shared/data/r2v): "
                      "walls, door gaps, windows, the plan's fixtures, furniture by room type");
  gen_cmd->add_flag("--no-furniture", gen.no_furniture, "with --plan: only the plan's fixtures, no furniture or props");
  gen_cmd->add_option("--set", gen.settings, "override an option: apartment.NAME=V, artefacts.NAME=V or scan.NAME=V (repeatable; "
                      "see docs/generator.md)");

  semvox::EvalArgs eval;
  CLI::App* eval_cmd = app.add_subcommand("eval", "score `semvox run` outputs against a generated apartment's ground truth "
                                          "or a real scan's furniture boxes or labelled points");
  eval_cmd->add_option("--pred", eval.pred_dir, "OUTDIR of semvox run")->required();
  auto* eval_gt = eval_cmd->add_option("--gt", eval.gt_dir, "directory written by semvox generate --seed N");
  auto* eval_boxes = eval_cmd->add_option("--boxes", eval.boxes_path,
                                          "real scan: ScanNet-style gt.json (axis_align_matrix, boxes_in_aligned_frame) or SUN RGB-D-style gt_boxes.tsv (yawed boxes; docs/metrics.md)");
  auto* eval_points = eval_cmd->add_option("--points", eval.points_path,
                                           "real scan: a PLY of labelled points in the scan's frame (x, y, z, NYU40 label), "
                                           "each scored by the nearest voxel within 7.5 cm (docs/metrics.md)");
  eval_gt->excludes(eval_boxes);
  eval_gt->excludes(eval_points);
  eval_boxes->excludes(eval_points);
  eval_cmd->add_option("-o,--output", eval.output, "JSON report path (default PRED/eval.json with --gt, none with --boxes or --points)");
  eval_cmd->add_flag("--json", eval.json, "print the JSON report on stdout instead of the table");
  eval_cmd->add_flag("-q,--quiet", quiet, "print warnings and errors only");

  semvox::TrainArgs train;
  CLI::App* train_cmd = app.add_subcommand("train", "train the per-view classifiers on generated apartments and write models/");
  train_cmd->add_option("-o,--output", train.outdir, "output directory for the model files (default models)");
  train_cmd->add_option("--train-seeds", train.train_seeds, "generator seeds to train on, e.g. 0-39 or 1,5,9");
  train_cmd->add_option("--val-seeds", train.val_seeds, "generator seeds to score on, e.g. 100-109");
  train_cmd->add_option("--max-rows", train.max_rows, "training rows kept per k-NN model, 0 = all")->check(CLI::NonNegativeNumber);
  train_cmd->add_option("--crf-holdout", train.crf_holdout, "last training seeds used only to learn the CRF weights")->check(CLI::NonNegativeNumber);
  train_cmd->add_flag("--voxel-crf", train.voxel_crf_only, "train only the Voxel-CRF (per-view models must already be in the output directory)");
  train_cmd->add_flag("--segments", train.segments_only, "train only the object-segment classifier and the \"other\" and item labellers (object_segments.knn, other_labels.knn, item_labels.knn)");
  train_cmd->add_flag("--room-shapes", train.room_shapes_only,
                      "train only the room-shape model (room_shape.json) on real R2V plans 0-299, validated on 300-399");
  train_cmd->add_flag("--room-type-statistics", train.room_type_statistics_only,
                      "recompute only the R2V fixture statistics of room_type_crf.json (training seeds + R2V plans 0-299); "
                      "its learned terms stay");
  train_cmd->add_flag("--room-type-knn", train.room_type_knn_only,
                      "rebuild only the per-view room-type k-NN (room_type_knn.bin) from the training seeds' views and "
                      "apartments built on R2V plans 0-299 (--room-type-plans)");
  train_cmd->add_flag("--room-type-evidence", train.room_type_evidence_only,
                      "relearn only the room-type CRF's evidence terms (confusion, SSVM weights, dense CRF) in room_type_crf.json "
                      "on apartments built on R2V plans 0-299 (--room-type-plans), their views classified by the models in the "
                      "output directory; the statistics stay");
  train_cmd->add_option("--room-type-evidence-seeds", train.room_type_evidence_seeds,
                        "generated apartments --room-type-evidence learns on beside the plans (default 40-79: apartments neither "
                        "the per-view classifier nor the room-type k-NN saw; empty: plans only)");
  train_cmd->add_option("--room-type-calibration-plans", train.room_type_calibration_plans,
                        "--room-type-evidence chooses the weights' scale on these R2V training plans (sorted indices A-B, "
                        "within 0-299; left out of the learning; default 250-299; empty: on the learning apartments)");
  train_cmd->add_option("--room-type-ssvm-runs", train.room_type_ssvm_runs,
                        "--room-type-evidence averages each variant's SSVM direction over this many runs (default 3)")
      ->check(CLI::Range(1, 20));
  train_cmd->add_option("--room-type-plans", train.room_type_plans,
                        "R2V training plans (the first N sorted, at most 300) whose apartments add rows to the room-type k-NN "
                        "(--room-type-knn) or teach the room-type evidence terms (--room-type-evidence)")
      ->check(CLI::Range(0, 300));
  train_cmd->add_option("--view-plans", train.view_plans,
                        "apartments built on the first N sorted R2V training plans (at most 300; furnished by room type) add "
                        "their views' superpixels to the per-view classifiers' training rows (default 0)")
      ->check(CLI::Range(0, 300));
  train_cmd->add_option("--room-type-knn-classes", train.room_type_knn_classes,
                        "--room-type-knn rows from the true classes of each view (truth, as `semvox train`) or from those the "
                        "per-view classifier OUTDIR/second.* predicts (predicted, as at run time)")
      ->check(CLI::IsMember({"truth", "predicted"}));
  train_cmd->add_option("--room-shape-features", train.room_shape_features,
                        "features of the room-shape model, comma-separated (log_area_m2, log_aspect, log_width_m, log_area_share, "
                        "log1p_connections, exterior_share); default: all");
  train_cmd->add_option("--r2v-dir", train.r2v_dir, "R2V plans (plan_*.txt) for --room-shapes and the room-type statistics "
                        "(default ../shared/data/r2v, relative to the working directory)");
  train_cmd->add_option("--segment-seeds", train.segment_seeds, "generator seeds for the object-segment classifier, e.g. 0-99");
  train_cmd->add_option("--segment-classifier", train.segment_classifier,
                        "object-segment classifier: knn (object_segments.knn, shipped) or forest (object_segments.forest; `semvox run` prefers it when present)")
      ->check(CLI::IsMember({"knn", "forest"}));
  train_cmd->add_option("--voxel-crf-seeds", train.voxel_crf_seeds, "generator seeds for the Voxel-CRF weights, e.g. 0-7");
  train_cmd->add_option("--voxel-crf-epochs", train.voxel_crf_epochs, "structural-SVM epochs of the Voxel-CRF")->check(CLI::PositiveNumber);
  train_cmd->add_option("--voxel-crf-style", train.voxel_crf_style,
                        "scans the Voxel-CRF learns on: flat (the generator's meshes; the default), randomised or mixed (alternating seeds), each writing voxel_crf.txt (used for flat-coloured meshes), or cloud (simulated fused clouds; writes voxel_crf_cloud.txt, used for point clouds and scanned meshes)")
      ->check(CLI::IsMember({"flat", "randomised", "randomized", "mixed", "cloud"}));
  train_cmd->add_option("--voxel-crf-appearance-weight", train.voxel_crf_appearance_weight,
                        "hold the Voxel-CRF's per-view evidence weight at this value instead of learning it (default: learned)")
      ->check(CLI::NonNegativeNumber);
  train_cmd->add_option("--style", train.style, "training views: flat (the generator's own colours; the shipped models) or randomised (palettes, textures, lighting, simulated clouds); validation is scored in both")
      ->check(CLI::IsMember({"randomised", "randomized", "flat"}));
  train_cmd->add_flag("-q,--quiet", quiet, "print warnings and errors only");

  semvox::RenderArgs render;
  CLI::App* render_cmd = app.add_subcommand("render", "render chosen views of a mesh or cloud into DIR for inspection");
  render_cmd->add_option("input", render.input, "mesh or point cloud, as for `semvox run`")->required();
  render_cmd->add_option("-o,--output", render.outdir, "output directory")->required();
  render_cmd->add_option("--pose", render.poses, "x,y,z,yaw_deg[,pitch_deg] in the input frame (repeatable); yaw 0 looks along +X")
      ->required()->take_all();
  render_cmd->add_option("--fov", render.horizontal_fov_deg, "horizontal field of view, degrees")->check(CLI::Range(2.0, 170.0));
  render_cmd->add_option("--width", render.width, "image width, pixels")->check(CLI::Range(16, 8192));
  render_cmd->add_option("--height", render.height, "image height, pixels")->check(CLI::Range(16, 8192));
  render_cmd->add_option("--voxel-size", render.voxel_size_m, "resolution of the per-pixel voxel keys, metres")->check(CLI::PositiveNumber);
  render_cmd->add_option("--config", render.config_path, "YAML configuration (render and input sections apply)");
  render_cmd->add_option("--up", render.up, "up axis of the input: auto, z, y, -y, x, -x, -z; write --up=-y")
      ->check(CLI::IsMember({"auto", "z", "y", "-y", "x", "-x", "-z", "+z", "+y", "+x"}));
  render_cmd->add_option("--scale", render.scale, "multiply coordinates into metres")->check(CLI::PositiveNumber);
  render_cmd->add_flag("-q,--quiet", quiet, "print warnings and errors only");

  semvox::RoomsArgs rooms_args;
  CLI::App* rooms_cmd = app.add_subcommand("rooms", "segment a 2D map image (0 occupied, 255 free) into rooms");
  rooms_cmd->add_option("map", rooms_args.map_path, "map image (PNG, PGM); pixels > 250 are free")->required();
  rooms_cmd->add_option("--resolution", rooms_args.resolution_m, "metres per pixel")->check(CLI::PositiveNumber);
  rooms_cmd->add_option("--method", rooms_args.method, "distance (default) or morphological")
      ->check(CLI::IsMember({"distance", "morphological"}));
  rooms_cmd->add_option("-o,--output", rooms_args.outdir, "output directory (rooms.png, rooms.geojson, rooms.svg)")->required();
  rooms_cmd->add_option("--config", rooms_args.config_path, "YAML configuration (its rooms section applies)");
  rooms_cmd->add_option("--gt", rooms_args.ground_truth_path, "ground truth (ipa _gt_segmentation.png): print recall and precision");
  rooms_cmd->add_flag("-q,--quiet", quiet, "print warnings and errors only");
  bool dump = false;
  semvox::ReportArgs report;
  CLI::App* report_cmd = app.add_subcommand("report", "(re)write OUTDIR/report.html from a run's outputs");
  report_cmd->add_option("outdir", report.outdir, "output directory of semvox run")->required();
  report_cmd->add_option("--config", report.config_path, "YAML configuration (its report section applies)");
  report_cmd->add_flag("--no-3d", report.no_3d, "leave the interactive 3D view out of the page");
  report_cmd->add_flag("-q,--quiet", quiet, "print warnings and errors only");
  semvox::RemoveArgs remove_args;
  CLI::App* remove_cmd = app.add_subcommand("remove", "remove objects from a run's map and complete the space behind them");
  remove_cmd->add_option("outdir", remove_args.outdir, "output directory of semvox run")->required();
  remove_cmd->add_option("-o,--output", remove_args.output, "output directory of the edited map");
  auto* rm_class = remove_cmd->add_option("--class", remove_args.classes, "NYU40 class to remove (name or id; repeatable)");
  auto* rm_inst = remove_cmd->add_option("--instance", remove_args.instances, "instance id to remove (see --list; repeatable)");
  auto* rm_all = remove_cmd->add_flag("--all-furniture", remove_args.all_furniture, "remove every furniture and props voxel");
  remove_cmd->add_flag("--list", remove_args.list, "print the instances (26-connected voxels of one label) and exit");
  rm_class->excludes(rm_inst)->excludes(rm_all);
  rm_inst->excludes(rm_all);
  remove_cmd->add_flag("-q,--quiet", quiet, "print warnings and errors only");
  CLI::App* labels_cmd = app.add_subcommand("labels", "print the NYU40 classes, their 13/4-class mappings and the room types (Markdown)");
  std::string check_path;
  semvox::BatchArgs batch;
  CLI::App* batch_cmd = app.add_subcommand("batch", "run many scans listed in MANIFEST into ROOT (resumable)");
  batch_cmd->add_option("manifest", batch.manifest, "one scan per line: INPUT or NAME INPUT")->required();
  batch_cmd->add_option("-o,--output", batch.root, "root output directory")->required();
  batch_cmd->add_option("-j,--jobs", batch.jobs, "scans run at once")->check(CLI::PositiveNumber);
  batch_cmd->add_option("--config", batch.config_path, "YAML configuration for every scan");

  CLI::App* config_cmd = app.add_subcommand("config", "print or check the configuration");
  config_cmd->add_flag("--dump", dump, "print every option with its default, units and range");
  config_cmd->add_option("--check", check_path, "validate a YAML configuration file");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::fprintf(stderr, "semvox: error: %s (hint: semvox %s--help)\n", e.what(),
                 app.get_subcommands().empty() ? "" : (app.get_subcommands()[0]->get_name() + " ").c_str());
    return 2;
  }
  // `semvox run` and `batch` print their stages and a summary by default, each step's detail with -v; the other
  // commands print what they do.
  if (quiet) semvox::SetLogLevel(semvox::LogLevel::kWarning);
  else if (verbose) semvox::SetLogLevel(semvox::LogLevel::kInfo);
  else if (*run_cmd || *batch_cmd) semvox::SetLogLevel(semvox::LogLevel::kNote);

  try {
    if (*run_cmd) {
      // The ONNX models load (and fail) before anything is written.
      auto onnx = std::make_shared<semvox::OnnxModels>();
      const semvox::Status st = semvox::LoadOnnxModels(run.onnx_paths, onnx.get());
      if (!st.ok()) return Report(st);
      if (onnx->any()) run.onnx = std::move(onnx);
      return Report(semvox::RunRunCommand(run));
    }
    if (*batch_cmd) return Report(semvox::RunBatch(batch));
    if (*gen_cmd) return Report(semvox::RunGenerate(gen));
    if (*eval_cmd) return Report(semvox::RunEval(eval));
    if (*rooms_cmd) return Report(semvox::RunRooms(rooms_args));
    if (*render_cmd) return Report(semvox::RunRender(render));
    if (*train_cmd)
      return Report(train.voxel_crf_only  ? semvox::RunTrainVoxelCrf(train)
                    : train.segments_only ? semvox::RunTrainSegments(train)
                    : train.room_shapes_only ? semvox::RunTrainRoomShapes(train)
                    : train.room_type_statistics_only ? semvox::RunTrainRoomTypeStatistics(train)
                    : train.room_type_knn_only ? semvox::RunTrainRoomTypeKnn(train)
                    : train.room_type_evidence_only ? semvox::RunTrainRoomTypeEvidence(train)
                                          : semvox::RunTrain(train));
    if (*report_cmd) return Report(semvox::RunReport(report));
    if (*remove_cmd) return Report(semvox::RunRemove(remove_args));
    if (*labels_cmd) return Report(semvox::RunLabels());
    if (*config_cmd) {
      semvox::PipelineConfig config;
      if (!check_path.empty()) {
        semvox::Status st = semvox::LoadConfigFile(check_path, &config);
        if (!st.ok()) return Report(st);
        std::printf("%s: ok\n", check_path.c_str());
      }
      if (dump || check_path.empty()) std::cout << semvox::DumpConfig(config);
      return 0;
    }
  } catch (const std::bad_alloc&) {
    semvox::RemovePendingTemporaries();
    return Report(semvox::Status::Internal("out of memory (hint: use larger voxels or raise the machine's memory)"));
  } catch (const std::exception& e) {
    semvox::RemovePendingTemporaries();
    return Report(semvox::Status::Internal(std::string("internal error: ") + e.what()));
  }
  return 0;
}
