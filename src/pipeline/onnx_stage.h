// The optional ONNX backend of the pipeline: the user's scene and segmentation networks
// (perception/onnx_models.h), loaded from the run's flags before anything is written.
//
//   --scene-model X.onnx  --scene-labels X.tsv   [--scene-input 224x224]
//   --object-model Y.onnx --object-labels Y.tsv  [--object-input 224x224]
//
// apps/main.cc calls LoadOnnxModels before RunPipeline and hands the models over in PipelineOptions::onnx, so
// a bad path, model or label map stops the run with one error line (exit code 2) and no output. Per view, the
// object model's PixelProbabilities replace the built-in classifier's per-pixel probabilities and the
// scene model's RoomTypeProbabilities replace the room-type evidence:
//
//   if (options.onnx && options.onnx->object) {
//     Result<ImageF32> q = options.onnx->object->PixelProbabilities(view);  // SecondLevel(), K per pixel
//     acc->AddClassifiedView(view, nullptr, q->data);
//     predicted = PixelArgmax(*q);                                      // for the built-in room evidence
//   }
//   if (options.onnx && options.onnx->scene) room = *options.onnx->scene->RoomTypeProbabilities(view);
#pragma once

#include <optional>
#include <string>

#include "core/image.h"
#include "core/status.h"
#include "perception/onnx_models.h"
#include "perception/label_levels.h"

namespace semvox {

// The networks and their label maps as the flags name them ("" = not given); input sizes "WxH", "" = 224x224.
struct OnnxModelPaths {
  std::string scene_model, scene_labels, scene_input_size;     // --scene-model, --scene-labels, --scene-input
  std::string object_model, object_labels, object_input_size;  // --object-model, --object-labels, --object-input
};

struct OnnxModels {
  std::optional<OnnxSceneModel> scene;    // --scene-model with --scene-labels.
  std::optional<OnnxObjectModel> object;  // --object-model with --object-labels.
  bool any() const { return scene.has_value() || object.has_value(); }
};

// Loads the models `paths` names (none when no ONNX flag is set). The object model's level is `level`
// (the semantic stage's SecondLevel()). A model without its label map, a label map without its model, a
// bad input size, a missing or unreadable model or a bad label map is kInvalidInput, naming the flag or
// file; `out` is then left empty.
Status LoadOnnxModels(const OnnxModelPaths& paths, const LabelLevel& level, OnnxModels* out);
inline Status LoadOnnxModels(const OnnxModelPaths& paths, OnnxModels* out) { return LoadOnnxModels(paths, SecondLevel(), out); }

// "WxH" -> width, height (each 1-8192); "" keeps the defaults.
Status ParseOnnxInputSize(const std::string& flag, const std::string& text, OnnxPreprocessing* preprocessing);

// The most probable class of every pixel of a per-pixel probability image (ties: the lower class).
Image<int32_t> PixelArgmax(const ImageF32& probabilities);

}  // namespace semvox
