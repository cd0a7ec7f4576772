#include "pipeline/onnx_stage.h"

#include <cstdlib>

#include "core/log.h"

namespace semvox {

Status ParseOnnxInputSize(const std::string& flag, const std::string& text, OnnxPreprocessing* preprocessing) {
  if (text.empty()) return Status::Ok();
  const std::string hint = "(hint: give WIDTHxHEIGHT in pixels, e.g. " + flag + " 224x224)";
  const size_t x = text.find_first_of("xX");
  auto number = [](const std::string& s, int* v) {
    if (s.empty() || s.size() > 4 || s.find_first_not_of("0123456789") != std::string::npos) return false;
    *v = std::atoi(s.c_str());
    return *v >= 1 && *v <= 8192;
  };
  int w = 0, h = 0;
  if (x == std::string::npos || !number(text.substr(0, x), &w) || !number(text.substr(x + 1), &h))
    return Status::InvalidInput(flag + " " + text + ": not an input size of 1-8192 x 1-8192 pixels " + hint);
  preprocessing->input_width = w;
  preprocessing->input_height = h;
  return Status::Ok();
}

Status LoadOnnxModels(const OnnxModelPaths& args, const LabelLevel& level, OnnxModels* out) {
  *out = OnnxModels{};
  auto pair_check = [](const std::string& model, const std::string& labels, const char* model_flag, const char* labels_flag) {
    if (!model.empty() && labels.empty())
      return Status::InvalidInput(std::string(model_flag) + " " + model + " needs " + labels_flag +
                                  " (hint: a label map, one 'NET_INDEX NAME' line per network class; see docs/perception.md)");
    if (model.empty() && !labels.empty())
      return Status::InvalidInput(std::string(labels_flag) + " " + labels + " is given without " + model_flag +
                                  " (hint: pass the .onnx network too)");
    return Status::Ok();
  };
  SEMVOX_RETURN_IF_ERROR(pair_check(args.scene_model, args.scene_labels, "--scene-model", "--scene-labels"));
  SEMVOX_RETURN_IF_ERROR(pair_check(args.object_model, args.object_labels, "--object-model", "--object-labels"));
  OnnxModels models;
  if (!args.scene_model.empty()) {
    OnnxSceneModelOptions options;
    SEMVOX_RETURN_IF_ERROR(ParseOnnxInputSize("--scene-input", args.scene_input_size, &options.preprocessing));
    Result<OnnxSceneModel> scene = OnnxSceneModel::Load(args.scene_model, args.scene_labels, options);
    if (!scene.ok()) return scene.status();
    SEMVOX_INFO("scene model " << args.scene_model << ": " << scene->num_network_classes() << " classes -> 12 room types");
    models.scene = std::move(scene).value();
  }
  if (!args.object_model.empty()) {
    OnnxObjectModelOptions options;
    SEMVOX_RETURN_IF_ERROR(ParseOnnxInputSize("--object-input", args.object_input_size, &options.preprocessing));
    Result<OnnxObjectModel> object = OnnxObjectModel::Load(args.object_model, args.object_labels, level, options);
    if (!object.ok()) return object.status();
    SEMVOX_INFO("object model " << args.object_model << ": " << object->num_network_classes() << " classes -> "
                                << level.num_classes() << " " << level.name << " classes");
    models.object = std::move(object).value();
  }
  *out = std::move(models);
  return Status::Ok();
}

Image<int32_t> PixelArgmax(const ImageF32& probabilities) {
  Image<int32_t> labels(probabilities.width, probabilities.height, 1, -1);
  const int K = probabilities.channels;
  for (size_t i = 0; i < labels.data.size(); ++i) {
    const float* p = probabilities.data.data() + i * size_t(K);
    int best = 0;
    for (int k = 1; k < K; ++k)
      if (p[k] > p[best]) best = k;
    labels.data[i] = K > 0 ? best : -1;
  }
  return labels;
}

}  // namespace semvox
