// Optional ONNX backend: a user's own networks, run by OpenCV DNN, in place of the
// built-in per-view classifiers.
//
//   Result<OnnxSceneModel> scene = OnnxSceneModel::Load("resnet18_places365.onnx", "places_labels.tsv");
//   Result<std::vector<double>> p = scene->RoomTypeProbabilities(view);   // 12 values, index = id - 1
//
//   Result<OnnxObjectModel> seg = OnnxObjectModel::Load("seg.onnx", "seg_labels.tsv", SecondLevel());
//   Result<ImageF32> q = seg->PixelProbabilities(view);   // view size, level.num_classes() channels
//
// * Scene model: a Places365-style classifier, one input [1,3,h,w], one output of C class scores
//   ([1,C] or [1,C,1,1]). Its classes are mapped to the 12 room types of room_types.tsv by a label map.
// * Object model: a semantic segmentation network, one input [1,3,h,w], one output [1,C,h',w'] (any
//   h' x w'; bilinearly resized to the view). Its classes are mapped to NYU40 ids by a label map, then to
//   the classes of a LabelLevel (label_levels.h) through level.class_of_nyu40.
//
// Label-map file (text, UTF-8), one network class a line:
//
//   # comment; blank lines are skipped
//   NET_INDEX <whitespace> TARGET
//
// NET_INDEX is the class's output channel (0-based); TARGET is the rest of the line: a name or an id.
// Room-type maps accept ids 1-12 and every name or alias of room_types.tsv (bathroom, shower, nursery,
// hallway, galley, laundromat, home office, closet, pantry, background, ...), Places365 paths such as
// "/l/living_room" included (core/label_aliases.h); NYU40 maps accept ids 0-40 and nyu40_classes.tsv
// names ("floor mat", "night stand", "refrigerator"). "-" (and "unknown" / "unlabeled" / id 0) marks a
// class as mapped to nothing; classes not listed are mapped to nothing as well. A network class may be
// listed once; several classes may share a target (their probabilities add up).
//
// Classes mapped to nothing: in a scene model their probability goes to "other" (id 12) by default, as the
// room-labelling paper's "background" class (Places365 scenes outside the 11 room types; room_types.tsv
// maps "background" to other) and as the built-in room evidence puts views with too little evidence there;
// with unmapped_to_other = false it is dropped and the 12 values renormalised (all to "other" when nothing
// is left). In an object model it is dropped per pixel and the level's classes renormalised (uniform when
// nothing is left), as are NYU40 ids the level ignores.
//
// Preprocessing: the RGB view is resized to input_width x input_height (area interpolation when shrinking,
// bilinear otherwise), each channel becomes (value * pixel_scale - mean[c]) / std[c] in R, G, B order
// (or B, G, R with bgr), NCHW. Defaults are those of the torchvision Places365 networks: 224 x 224,
// ImageNet mean and std on [0, 1] values, RGB. Outputs are logits or probabilities: by default (kAuto) an
// output whose every pixel holds values in [0, 1] summing to 1 (within 1e-3) is taken as probabilities,
// anything else as logits, which get a softmax.
//
// Pixels where the view hits nothing are black in view.rgb and classified like any other; callers use
// view.hit(). The models are thread-safe: forward passes are serialised (an OpenCV Net is not re-entrant);
// OpenCV parallelises each pass itself. Deterministic on one machine.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/status.h"
#include "perception/room_evidence.h"
#include "perception/label_levels.h"
#include "render/view_renderer.h"

namespace semvox {

enum class OnnxOutputKind {
  kAuto,           // Probabilities when every pixel's values lie in [0, 1] and sum to 1 (1e-3), else logits.
  kLogits,         // Always apply a softmax over the classes.
  kProbabilities,  // Never: negative values are clamped to 0 and every pixel renormalised.
};

struct OnnxPreprocessing {
  int input_width = 224;               // Network input width, pixels. [1, 8192].
  int input_height = 224;              // Network input height, pixels. [1, 8192].
  double pixel_scale = 1.0 / 255.0;    // 8-bit value -> network units before mean and std. > 0.
  std::array<double, 3> mean = {0.485, 0.456, 0.406};  // Subtracted per channel (R, G, B), network units.
  std::array<double, 3> std = {0.229, 0.224, 0.225};   // Divides per channel (R, G, B). > 0.
  bool bgr = false;                    // Feed the channels as B, G, R (Caffe-converted networks).
  OnnxOutputKind output = OnnxOutputKind::kAuto;

  bool Check(std::string* error) const;
};

struct OnnxSceneModelOptions {
  OnnxPreprocessing preprocessing;
  // Probability of network classes the label map leaves unmapped goes to "other" (true) or is dropped and
  // the room types renormalised (false).
  bool unmapped_to_other = true;

  bool Check(std::string* error) const { return preprocessing.Check(error); }
};

struct OnnxObjectModelOptions {
  OnnxPreprocessing preprocessing;

  bool Check(std::string* error) const { return preprocessing.Check(error); }
};

// A parsed label-map file.
enum class LabelMapVocabulary { kRoomType, kNyu40 };
struct OnnxLabelMap {
  // Per network class index (size: largest listed index + 1): room_types.tsv id 1-12 or NYU40 id 1-40,
  // -1 when mapped to nothing.
  std::vector<int> target_of_class;
  int listed = 0;  // Lines read.
};

// Errors name the file and line: "seg.tsv:7: 'flor' is not a NYU40 class (hint: ...)".
Result<OnnxLabelMap> ReadOnnxLabelMap(const std::string& path, LabelMapVocabulary vocabulary);
Result<OnnxLabelMap> ParseOnnxLabelMap(const std::string& text, const std::string& path, LabelMapVocabulary vocabulary);

class OnnxSceneModel {
 public:
  // Reads the network and the label map and runs one probe pass on a blank input, so that a bad model,
  // a wrong input size or a label-map index beyond the network's classes fails here.
  static Result<OnnxSceneModel> Load(const std::string& onnx_path, const std::string& label_map_path,
                                     const OnnxSceneModelOptions& options = {});

  // P(room type | view): kNumRoomTypeClasses (12) values, index = room_types.tsv id - 1, summing to 1.
  Result<std::vector<double>> RoomTypeProbabilities(const RenderedView& view) const;
  // The network's own C class probabilities (softmax applied to logits).
  Result<std::vector<double>> NetworkProbabilities(const RenderedView& view) const;

  int num_network_classes() const;
  const OnnxSceneModelOptions& options() const;

 private:
  struct Impl;
  explicit OnnxSceneModel(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<Impl> impl_;
};

class OnnxObjectModel {
 public:
  // As OnnxSceneModel::Load; `level` gives the classes PixelProbabilities returns.
  static Result<OnnxObjectModel> Load(const std::string& onnx_path, const std::string& label_map_path,
                                      const LabelLevel& level, const OnnxObjectModelOptions& options = {});

  // Per-pixel P(class of level()): the view's size, level().num_classes() channels, pixel-major, every
  // pixel summing to 1 (the same layout as PixelProbabilities in view_crf.h).
  Result<ImageF32> PixelProbabilities(const RenderedView& view) const;
  // Per-pixel mass over NYU40 ids: the view's size, kNumNyu40 (41) channels summing to 1; channel 0 holds
  // the classes mapped to nothing. One forward pass serves several levels via Nyu40ToLevelProbabilities.
  Result<ImageF32> Nyu40PixelProbabilities(const RenderedView& view) const;

  int num_network_classes() const;
  const LabelLevel& level() const;
  const OnnxObjectModelOptions& options() const;

 private:
  struct Impl;
  explicit OnnxObjectModel(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<Impl> impl_;
};

// NYU40 mass (kNumNyu40 channels) -> the level's classes: sums the ids of every class, drops the ids the
// level ignores (class_of_nyu40 = -1, id 0 always), renormalises; uniform where nothing is left.
ImageF32 Nyu40ToLevelProbabilities(const ImageF32& nyu40, const LabelLevel& level);

}  // namespace semvox
