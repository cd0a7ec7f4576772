#include "pipeline/voxel_crf_training.h"

#include <chrono>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "core/labels.h"
#include "core/log.h"
#include "eval/evaluate.h"
#include "perception/training_data.h"
#include "pipeline/pipeline_config.h"
#include "pipeline/semantic_evidence.h"
#include "pipeline/voxel_crf_examples.h"
#include "scenegen/apartment.h"
#include "scenegen/scan_artefacts.h"

namespace semvox {

Status TrainVoxelCrf(const VoxelCrfTrainingOptions& args) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<uint64_t>& seeds = args.seeds;
  const PipelineConfig config;  // The defaults `semvox run` uses.
  const LabelLevel level = SecondLevel();
  const int K = level.num_classes();
  struct Item {
    Scene scene;
    VoxelMap map;
    std::unique_ptr<ViewRenderer> renderer;
    SemanticEvidence evidence;
    std::vector<int> gt;
  };
  std::deque<Item> items;
  std::vector<double> layout_counts;
  std::map<int, size_t> other_ids;  // NYU40 ids that fall in "other", by voxel count.
  const int other_class = K - 1;
  const bool mixed = args.style == "mixed";
  // cloud: randomised scans that are all simulated fused clouds; the weights go to voxel_crf_cloud.txt,
  // which `semvox run` uses for point-cloud input (SemanticStageOptions::crf_model).
  const bool cloud = args.style == "cloud";
  TrainingStyle fixed_style = TrainingStyle::kFlat;
  if (cloud) fixed_style = TrainingStyle::kRandomised;
  else if (!mixed && !ParseTrainingStyle(args.style, &fixed_style))
    return Status::InvalidInput("--voxel-crf-style = '" + args.style + "': expected flat, randomised, cloud or mixed");
  const std::string model_name = cloud ? "voxel_crf_cloud" : "voxel_crf";
  // The models `semvox run` uses on such a scan (the CRF weights' choice does not change the evidence).
  Result<SemanticModels> models = SemanticModels::Load(args.models_dir, VoxelCrfModelChoice::kMesh);
  if (!models.ok()) return models.status();
  for (size_t seed_index = 0; seed_index < seeds.size(); ++seed_index) {
    const uint64_t seed = seeds[seed_index];
    ApartmentOptions ao;
    ao.seed = seed;
    ao.max_rooms = 4;
    // Flat scans (the generator's meshes) and randomised ones (palettes, textures, lighting, simulated fused
    // clouds of random spacing: what a real scan looks like), alternating when mixed, so that the weights
    // see the evidence of both.
    TrainingViewsOptions style;
    style.style = mixed ? (seed_index % 2 == 0 ? TrainingStyle::kFlat : TrainingStyle::kRandomised) : fixed_style;
    if (cloud) style.cloud_probability = 1.0;
    ao.shape_variety = style.style == TrainingStyle::kRandomised;
    Result<Apartment> apt = GenerateApartment(ao);
    if (!apt.ok()) return apt.status();
    Item& it = items.emplace_back();
    Result<Scene> scan = MakeTrainingScan(*apt, seed, style);
    if (!scan.ok()) return scan.status();
    it.scene = std::move(scan).value();
    Result<VoxelMap> map = Voxelize(it.scene, config.voxelize);
    if (!map.ok()) return map.status();
    it.map = std::move(map).value();
    Result<ViewRenderer> renderer = ViewRenderer::Create(it.scene);
    if (!renderer.ok()) return renderer.status();
    it.renderer = std::make_unique<ViewRenderer>(std::move(renderer).value());
    SemanticStageOptions semantic_options = config.semantic;  // As `semvox run` resolves auto for this scan.
    semantic_options.view_selection = ResolveViewSelection(semantic_options.view_selection, it.scene);
    Result<std::unique_ptr<SemanticEvidenceBuilder>> builder =
        SemanticEvidenceBuilder::Create(it.map, *it.renderer, semantic_options, *models);
    if (!builder.ok()) return builder.status();
    Result<ViewSet> views = RenderViews(*it.renderer, it.map, config.render, (*builder)->DepthSink());
    if (!views.ok()) return views.status();
    SEMVOX_RETURN_IF_ERROR((*builder)->ClassifyViews(views->positions));
    it.evidence = std::move(**builder).Finish();
    const VoxelLabels gt_voxels = VoxelizeLabeledMesh(apt->mesh, config.voxelize.voxel_size_m);
    const std::unordered_map<uint64_t, int> gt_map(gt_voxels.begin(), gt_voxels.end());
    it.gt = GroundTruthNodeLabels(it.map.grid, it.evidence, level, gt_map);
    AddLayoutCounts(it.map, it.evidence, K, it.gt, &layout_counts);
    for (const auto& [key, id] : gt_voxels)
      if (id > 0 && id < kNumNyu40 && level.class_of_nyu40[size_t(id)] == other_class) ++other_ids[id];
    it.renderer.reset();
    size_t occupied = 0;
    for (int g : it.gt) occupied += g > 0;
    SEMVOX_INFO("voxel CRF training: seed " << seed << " (" << TrainingStyleName(style.style) << "): " << it.gt.size() << " nodes, " << occupied << " occupied in the ground truth");
  }
  // The model: NYU40 id per class ("other" -> its most frequent id in the training apartments).
  std::vector<int> nyu40 = Nyu40OfClasses(level);
  size_t best = 0;
  for (const auto& [id, count] : other_ids)
    if (count > best) best = count, nyu40[size_t(other_class)] = id;
  VoxelCrfModel model = VoxelCrfModel::Default(nyu40, level.class_names);
  model.layout = LayoutPrior::FromCounts(K, layout_counts);
  std::vector<VoxelCrfTrainingExample> examples;
  // The weights are learned on the layout prior as counted (as every shipped model was); dividing it by the
  // class frequencies depends on the model's appearance weight, which learning is still choosing.
  VoxelCrfOptions crf_options = config.semantic.crf;
  crf_options.layout_frequency_power = 0;
  for (Item& it : items) examples.push_back(TrainingExample(it.map, it.evidence, crf_options, it.gt, model));
  // Training error of the initial and the learned weights (plain inference, ground-truth visibility).
  auto training_error = [&](const std::array<double, kNumVoxelCrfWeights>& w) -> Result<double> {
    double sum = 0;
    for (const auto& ex : examples) {
      std::vector<CrfLabel> labels;
      CrfSolverSummary s;
      SEMVOX_RETURN_IF_ERROR(MinimizeWithAlphaExpansion(ex.problem.Energy(w), AlphaExpansionOptions{}, &labels, &s));
      sum += HammingLoss(std::vector<int>(labels.begin(), labels.end()), ex.gt);
    }
    return sum / double(examples.size());
  };
  Result<double> before = training_error(model.w);
  if (!before.ok()) return before.status();
  VoxelCrfLearningOptions lo;
  lo.epochs = args.epochs;
  if (args.appearance_weight >= 0) {
    model.w[kWAppearance] = args.appearance_weight;
    lo.frozen[kWAppearance] = true;
  }
  VoxelCrfLearningSummary summary;
  Result<std::array<double, kNumVoxelCrfWeights>> w = LearnVoxelCrfWeights(examples, model.w, lo, &summary);
  if (!w.ok()) return w.status();
  model.w = *w;
  Result<double> after = training_error(model.w);
  if (!after.ok()) return after.status();
  SEMVOX_RETURN_IF_ERROR(model.Save((std::filesystem::path(args.models_dir) / (model_name + ".txt")).string()));
  nlohmann::ordered_json report;
  report["seeds"] = args.seeds_text;
  report["style"] = args.style;
  report["appearance_weight_held"] = args.appearance_weight >= 0;
  report["epochs"] = lo.epochs;
  report["learning_rate"] = lo.learning_rate;
  report["regularization"] = lo.regularization;
  report["loss_augmented_hamming_per_epoch"] = summary.loss_per_epoch;
  report["hinge_per_epoch"] = summary.hinge_per_epoch;
  report["training_error_default_weights"] = *before;
  report["training_error_learned_weights"] = *after;
  report["weights"] = std::vector<double>(model.w.begin(), model.w.end());
  report["other_class_nyu40"] = nyu40[size_t(other_class)];
  report["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  SEMVOX_RETURN_IF_ERROR(WriteFileAtomic((std::filesystem::path(args.models_dir) / (model_name + "_report.json")).string(), report.dump(2) + "\n"));
  SEMVOX_INFO("voxel CRF training: per-voxel training error " << *before << " with the default weights, " << *after
                                                              << " learned; " << args.models_dir << "/" << model_name << ".txt");
  return Status::Ok();
}

}  // namespace semvox
