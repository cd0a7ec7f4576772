// The optional ONNX backend of `semvox run`: the user's scene and segmentation networks
// (perception/onnx_models.h), loaded from the run's flags before anything is written.
//
//   --scene-model X.onnx  --scene-labels X.tsv   [--scene-input 224x224]
//   --object-model Y.onnx --object-labels Y.tsv  [--object-input 224x224]
//
// main.cc calls LoadOnnxModels before RunPipeline and hands the models over in RunArgs::onnx, so a bad
// path, model or label map stops the run with one error line (exit code 2) and no output. Per view, the
// object model's PixelProbabilities replace the built-in classifier's per-pixel probabilities and the
// scene model's RoomTypeProbabilities replace the room-type evidence:
//
//   if (args.onnx && args.onnx->object) {
//     Result<ImageF32> q = args.onnx->object->PixelProbabilities(view);  // SecondLevel(), K per pixel
//     acc->AddClassifiedView(view, nullptr, q->data);
//     predicted = PixelArgmax(*q);                                      // for the built-in room evidence
//   }
//   if (args.onnx && args.onnx->scene) room = *args.onnx->scene->RoomTypeProbabilities(view);
#pragma once

#include <optional>
#include <string>

#include "apps/commands.h"
#include "core/image.h"
#include "core/status.h"
#include "perception/onnx_models.h"
#include "perception/training_data.h"

namespace semvox {

struct OnnxModels {
  std::optional<OnnxSceneModel> scene;    // --scene-model with --scene-labels.
  std::optional<OnnxObjectModel> object;  // --object-model with --object-labels.
  bool any() const { return scene.has_value() || object.has_value(); }
};

// Loads the models `args` names (none when no ONNX flag is set). The object model's level is `level`
// (the semantic stage's SecondLevel()). A model without its label map, a label map without its model, a
// bad input size, a missing or unreadable model or a bad label map is kInvalidInput, naming the flag or
// file; `out` is then left empty.
Status LoadOnnxModels(const RunArgs& args, const LabelLevel& level, OnnxModels* out);
inline Status LoadOnnxModels(const RunArgs& args, OnnxModels* out) { return LoadOnnxModels(args, SecondLevel(), out); }

// "WxH" -> width, height (each 1-8192); "" keeps the defaults.
Status ParseOnnxInputSize(const std::string& flag, const std::string& text, OnnxPreprocessing* preprocessing);

// The most probable class of every pixel of a per-pixel probability image (ties: the lower class).
Image<int32_t> PixelArgmax(const ImageF32& probabilities);

}  // namespace semvox
