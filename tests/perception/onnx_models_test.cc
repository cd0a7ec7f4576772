// The ONNX backend and its `semvox run` flags (pipeline/onnx_stage.h) on tiny networks this
// test writes with python3-onnx: a 1x1 convolution (each pixel's class scores are a linear function of its
// colour) as the segmentation network, global average pooling + Gemm as the scene network. Every output is
// checked against the same maths done here by hand. Skips when python3 with the onnx module is missing.
#include "perception/onnx_models.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "pipeline/onnx_stage.h"
#include "core/label_aliases.h"
#include "core/labels.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

// Writes an ONNX model from a JSON spec: kind "seg" (Conv 1x1, output [1,K,h,w]) or "scene"
// (GlobalAveragePool, Flatten, Gemm, output [1,K]); optional Softmax over the classes; opset 13.
constexpr const char* kMakeModel = R"PY(
import json, sys
import numpy as np
import onnx
from onnx import helper, numpy_helper, TensorProto
spec = json.load(open(sys.argv[1]))
h, w = spec["h"], spec["w"]
W = np.array(spec["weights"], dtype=np.float32)
B = np.array(spec["bias"], dtype=np.float32)
K = W.shape[0]
nodes, inits = [], []
if spec["kind"] == "seg":
    inits += [numpy_helper.from_array(W.reshape(K, 3, 1, 1), "W"), numpy_helper.from_array(B, "B")]
    nodes.append(helper.make_node("Conv", ["input", "W", "B"], ["scores"], kernel_shape=[1, 1]))
    shape = [1, K, h, w]
else:
    nodes.append(helper.make_node("GlobalAveragePool", ["input"], ["pooled"]))
    nodes.append(helper.make_node("Flatten", ["pooled"], ["flat"], axis=1))
    inits += [numpy_helper.from_array(W, "W"), numpy_helper.from_array(B, "B")]
    nodes.append(helper.make_node("Gemm", ["flat", "W", "B"], ["scores"], transB=1))
    shape = [1, K]
out = "scores"
if spec["softmax"]:
    nodes.append(helper.make_node("Softmax", ["scores"], ["probs"], axis=1))
    out = "probs"
graph = helper.make_graph(nodes, "tiny", [helper.make_tensor_value_info("input", TensorProto.FLOAT, [1, 3, h, w])],
                          [helper.make_tensor_value_info(out, TensorProto.FLOAT, shape)], inits)
model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 13)])
model.ir_version = 7
onnx.checker.check_model(model)
onnx.save(model, sys.argv[2])
)PY";

// Debian's python3 first (a user's python3 on PATH may lack the python3-onnx package).
std::string PythonWithOnnx() {
  for (const char* py : {"/usr/bin/python3", "python3"}) {
    const std::string cmd = std::string(py) + " -c 'import onnx, numpy' > /dev/null 2>&1";
    if (std::system(cmd.c_str()) == 0) return py;
  }
  return "";
}

#define REQUIRE_PYTHON_ONNX()                                                                   \
  const std::string python = PythonWithOnnx();                                                  \
  if (python.empty()) GTEST_SKIP() << "python3 with the onnx module (Debian python3-onnx) is missing"

using Weights = std::vector<std::array<double, 3>>;

std::string Json(const std::string& kind, int w, int h, const Weights& weights, const std::vector<double>& bias, bool softmax) {
  std::ostringstream s;
  s.precision(9);
  s << "{\"kind\":\"" << kind << "\",\"w\":" << w << ",\"h\":" << h << ",\"softmax\":" << (softmax ? "true" : "false")
    << ",\"weights\":[";
  for (size_t k = 0; k < weights.size(); ++k)
    s << (k ? "," : "") << "[" << weights[k][0] << "," << weights[k][1] << "," << weights[k][2] << "]";
  s << "],\"bias\":[";
  for (size_t k = 0; k < bias.size(); ++k) s << (k ? "," : "") << bias[k];
  s << "]}";
  return s.str();
}

std::string MakeModel(const std::string& python, const testing::ScratchDir& dir, const std::string& name,
                      const std::string& spec) {
  const std::string script = dir.File("make_model.py"), spec_path = dir.File(name + ".json"), out = dir.File(name + ".onnx");
  testing::WriteText(script, kMakeModel);
  testing::WriteText(spec_path, spec);
  const std::string cmd = python + " " + script + " " + spec_path + " " + out;
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return out;
}

// A hand-built view: four colour quadrants, every pixel a hit.
const std::array<std::array<uint8_t, 3>, 4> kQuadrantColours = {{{200, 30, 40}, {20, 180, 60}, {40, 50, 210}, {128, 128, 128}}};
int Quadrant(int x, int y, int w, int h) { return (x < w / 2 ? 0 : 1) + (y < h / 2 ? 0 : 2); }

RenderedView QuadrantView(int w, int h) {
  RenderedView v;
  v.rgb = ImageRgb8(w, h, 3);
  v.depth = ImageF32(w, h, 1, 2.0f);
  v.primitive = Image<int32_t>(w, h, 1, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) v.rgb.at(x, y, c) = kQuadrantColours[size_t(Quadrant(x, y, w, h))][size_t(c)];
  v.hit_pixels = size_t(w) * size_t(h);
  return v;
}

// The default preprocessing by hand: (v / 255 - mean) / std, R, G, B.
std::array<double, 3> Normalised(const std::array<double, 3>& rgb) {
  const OnnxPreprocessing p;
  std::array<double, 3> x{};
  for (int c = 0; c < 3; ++c) x[size_t(c)] = (rgb[size_t(c)] / 255.0 - p.mean[size_t(c)]) / p.std[size_t(c)];
  return x;
}

std::vector<double> Softmax(const Weights& weights, const std::vector<double>& bias, const std::array<double, 3>& x) {
  std::vector<double> z(weights.size());
  double top = -1e300, sum = 0;
  for (size_t k = 0; k < weights.size(); ++k) {
    z[k] = bias[k] + weights[k][0] * x[0] + weights[k][1] * x[1] + weights[k][2] * x[2];
    top = std::max(top, z[k]);
  }
  for (double& v : z) sum += (v = std::exp(v - top));
  for (double& v : z) v /= sum;
  return z;
}

// Five network classes; class 3 maps to nothing.
const Weights kSegWeights = {{2.0, -1.0, -1.0}, {-1.0, 2.0, -0.5}, {-0.5, -0.5, 2.0}, {0.3, 0.3, 0.3}, {0.5, 0.0, 0.5}};
const std::vector<double> kSegBias = {0.1, -0.2, 0.0, 0.4, -0.3};
constexpr const char* kSegLabels =
    "# tiny segmentation network -> NYU40\n"
    "0\twall\n"
    "1\tfloor\n"
    "2 bed   # a trailing comment\n"
    "\n"
    "3\t-\n"
    "4\t18\n";  // pillow

// NYU-4 probabilities of a colour by hand: wall -> structure, floor -> ground, bed -> furniture,
// pillow -> props; class 3 dropped and the rest renormalised.
std::vector<double> HandNyu4(const std::array<uint8_t, 3>& colour) {
  const std::vector<double> p = Softmax(kSegWeights, kSegBias, Normalised({double(colour[0]), double(colour[1]), double(colour[2])}));
  std::vector<double> q = {p[1], p[0], p[2], p[4]};  // ground, structure, furniture, props.
  const double kept = 1.0 - p[3];
  for (double& v : q) v /= kept;
  return q;
}

TEST(OnnxObjectModel, PixelProbabilitiesEqualTheHandComputedSoftmaxThroughTheLabelMap) {
  REQUIRE_PYTHON_ONNX();
  testing::ScratchDir dir("onnx_seg");
  const int w = 40, h = 30;
  const std::string model = MakeModel(python, dir, "seg", Json("seg", w, h, kSegWeights, kSegBias, false));
  testing::WriteText(dir.File("seg.tsv"), kSegLabels);
  OnnxObjectModelOptions options;
  options.preprocessing.input_width = w;
  options.preprocessing.input_height = h;
  Result<OnnxObjectModel> m = OnnxObjectModel::Load(model, dir.File("seg.tsv"), Nyu4Level(), options);
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->num_network_classes(), 5);
  const RenderedView view = QuadrantView(w, h);
  Result<ImageF32> q = m->PixelProbabilities(view);
  ASSERT_TRUE(q.ok()) << q.status().message();
  ASSERT_EQ(q->width, w);
  ASSERT_EQ(q->height, h);
  ASSERT_EQ(q->channels, 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::vector<double> want = HandNyu4(kQuadrantColours[size_t(Quadrant(x, y, w, h))]);
      double sum = 0;
      for (int c = 0; c < 4; ++c) {
        EXPECT_NEAR(q->at(x, y, c), want[size_t(c)], 1e-5) << x << "," << y << " class " << c;
        sum += q->at(x, y, c);
      }
      EXPECT_NEAR(sum, 1.0, 1e-5);
    }
  // The NYU40 mass keeps the unmapped class in channel 0.
  Result<ImageF32> nyu40 = m->Nyu40PixelProbabilities(view);
  ASSERT_TRUE(nyu40.ok());
  ASSERT_EQ(nyu40->channels, kNumNyu40);
  const std::vector<double> p = Softmax(kSegWeights, kSegBias, Normalised({200, 30, 40}));
  EXPECT_NEAR(nyu40->at(0, 0, 0), p[3], 1e-5);
  EXPECT_NEAR(nyu40->at(0, 0, nyu40::kWall), p[0], 1e-5);
  EXPECT_NEAR(nyu40->at(0, 0, nyu40::kPillow), p[4], 1e-5);
  // The colour rules: red is wall (structure), green floor (ground), blue bed (furniture).
  EXPECT_GT(q->at(0, 0, 1), 0.5);
  EXPECT_GT(q->at(w - 1, 0, 0), 0.5);
  EXPECT_GT(q->at(0, h - 1, 2), 0.5);
}

TEST(OnnxObjectModel, SoftmaxInsideTheNetworkGivesTheSameProbabilitiesAsLogits) {
  REQUIRE_PYTHON_ONNX();
  testing::ScratchDir dir("onnx_seg_softmax");
  const int w = 24, h = 16;
  const std::string logits = MakeModel(python, dir, "logits", Json("seg", w, h, kSegWeights, kSegBias, false));
  const std::string probs = MakeModel(python, dir, "probs", Json("seg", w, h, kSegWeights, kSegBias, true));
  testing::WriteText(dir.File("seg.tsv"), kSegLabels);
  OnnxObjectModelOptions options;
  options.preprocessing.input_width = w;
  options.preprocessing.input_height = h;
  Result<OnnxObjectModel> a = OnnxObjectModel::Load(logits, dir.File("seg.tsv"), SecondLevel(), options);
  Result<OnnxObjectModel> b = OnnxObjectModel::Load(probs, dir.File("seg.tsv"), SecondLevel(), options);
  ASSERT_TRUE(a.ok() && b.ok());
  const RenderedView view = QuadrantView(w, h);
  Result<ImageF32> qa = a->PixelProbabilities(view), qb = b->PixelProbabilities(view);
  ASSERT_TRUE(qa.ok() && qb.ok());
  ASSERT_EQ(qa->channels, SecondLevel().num_classes());
  double worst = 0;
  for (size_t i = 0; i < qa->data.size(); ++i) worst = std::max(worst, double(std::abs(qa->data[i] - qb->data[i])));
  EXPECT_LT(worst, 1e-5);
  // Second level: pillow is "other"; wall, floor and bed their own classes.
  const LabelLevel level = SecondLevel();
  const std::vector<double> want = HandNyu4(kQuadrantColours[0]);  // ground, structure, furniture, props
  EXPECT_NEAR(qa->at(0, 0, level.class_of_nyu40[nyu40::kWall]), want[1], 1e-5);
  EXPECT_NEAR(qa->at(0, 0, level.class_of_nyu40[nyu40::kFloor]), want[0], 1e-5);
  EXPECT_NEAR(qa->at(0, 0, level.class_of_nyu40[nyu40::kBed]), want[2], 1e-5);
  EXPECT_NEAR(qa->at(0, 0, level.class_of_nyu40[nyu40::kPillow]), want[3], 1e-5);
  // kProbabilities takes the scores as they are: logits clamped at 0 and renormalised, by hand.
  OnnxObjectModelOptions forced = options;
  forced.preprocessing.output = OnnxOutputKind::kProbabilities;
  Result<OnnxObjectModel> c = OnnxObjectModel::Load(logits, dir.File("seg.tsv"), SecondLevel(), forced);
  ASSERT_TRUE(c.ok());
  Result<ImageF32> qc = c->PixelProbabilities(view);
  ASSERT_TRUE(qc.ok());
  const std::array<double, 3> x = Normalised({200, 30, 40});
  std::vector<double> z(kSegWeights.size());
  for (size_t k = 0; k < z.size(); ++k)
    z[k] = std::max(0.0, kSegBias[k] + kSegWeights[k][0] * x[0] + kSegWeights[k][1] * x[1] + kSegWeights[k][2] * x[2]);
  const double mapped = z[0] + z[1] + z[2] + z[4];  // Class 3 maps to nothing.
  EXPECT_NEAR(qc->at(0, 0, level.class_of_nyu40[nyu40::kWall]), z[0] / mapped, 1e-5);
  EXPECT_NEAR(qc->at(0, 0, level.class_of_nyu40[nyu40::kFloor]), z[1] / mapped, 1e-5);
  EXPECT_NEAR(qc->at(0, 0, level.class_of_nyu40[nyu40::kPillow]), z[4] / mapped, 1e-5);
}

TEST(OnnxObjectModel, OutputsAtAnotherSizeAreResizedToTheView) {
  REQUIRE_PYTHON_ONNX();
  testing::ScratchDir dir("onnx_seg_resize");
  const int w = 64, h = 48, nw = 32, nh = 24;
  const std::string model = MakeModel(python, dir, "seg", Json("seg", nw, nh, kSegWeights, kSegBias, false));
  testing::WriteText(dir.File("seg.tsv"), kSegLabels);
  OnnxObjectModelOptions options;
  options.preprocessing.input_width = nw;
  options.preprocessing.input_height = nh;
  Result<OnnxObjectModel> m = OnnxObjectModel::Load(model, dir.File("seg.tsv"), Nyu4Level(), options);
  ASSERT_TRUE(m.ok()) << m.status().message();
  Result<ImageF32> q = m->PixelProbabilities(QuadrantView(w, h));
  ASSERT_TRUE(q.ok()) << q.status().message();
  ASSERT_EQ(q->width, w);
  ASSERT_EQ(q->height, h);
  // Away from the quadrant borders (4 px: the two bilinear resizes blend at most 2 network pixels), each
  // pixel is its colour's hand-computed distribution; everywhere the classes sum to one.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double sum = 0;
      for (int c = 0; c < 4; ++c) sum += q->at(x, y, c);
      EXPECT_NEAR(sum, 1.0, 1e-5);
      if (std::abs(x - w / 2) < 4 || std::abs(y - h / 2) < 4) continue;
      const std::vector<double> want = HandNyu4(kQuadrantColours[size_t(Quadrant(x, y, w, h))]);
      for (int c = 0; c < 4; ++c) EXPECT_NEAR(q->at(x, y, c), want[size_t(c)], 1e-4) << x << "," << y;
    }
}

// Scene network: three classes over the mean colour.
const Weights kSceneWeights = {{1.5, -0.5, 0.2}, {-0.7, 1.1, 0.4}, {0.2, 0.3, -1.2}, {0.0, 0.5, 0.5}};
const std::vector<double> kSceneBias = {0.2, 0.0, -0.1, 0.3};
constexpr const char* kSceneLabels =
    "0\t/b/bedroom\n"   // Places365 path -> 2 bedroom
    "1\tgalley\n"       // alias -> 6 kitchen
    "2\t8\n";           // id -> living_room; class 3 unlisted

std::vector<double> HandScene(const std::array<double, 3>& mean_rgb, bool unmapped_to_other) {
  const std::vector<double> p = Softmax(kSceneWeights, kSceneBias, Normalised(mean_rgb));
  std::vector<double> rooms(12, 0.0);
  rooms[1] = p[0];
  rooms[5] = p[1];
  rooms[7] = p[2];
  if (unmapped_to_other) {
    rooms[11] = p[3];
  } else {
    for (double& v : rooms) v /= 1.0 - p[3];
  }
  return rooms;
}

TEST(OnnxSceneModel, RoomTypeProbabilitiesEqualTheHandComputedPooledSoftmax) {
  REQUIRE_PYTHON_ONNX();
  testing::ScratchDir dir("onnx_scene");
  const int w = 40, h = 30;
  const std::string model = MakeModel(python, dir, "scene", Json("scene", w, h, kSceneWeights, kSceneBias, false));
  testing::WriteText(dir.File("scene.tsv"), kSceneLabels);
  OnnxSceneModelOptions options;
  options.preprocessing.input_width = w;
  options.preprocessing.input_height = h;
  const RenderedView view = QuadrantView(w, h);
  std::array<double, 3> mean{};
  for (const auto& c : kQuadrantColours)
    for (int k = 0; k < 3; ++k) mean[size_t(k)] += c[size_t(k)] / 4.0;
  for (bool to_other : {true, false}) {
    options.unmapped_to_other = to_other;
    Result<OnnxSceneModel> m = OnnxSceneModel::Load(model, dir.File("scene.tsv"), options);
    ASSERT_TRUE(m.ok()) << m.status().message();
    EXPECT_EQ(m->num_network_classes(), 4);
    Result<std::vector<double>> p = m->RoomTypeProbabilities(view);
    ASSERT_TRUE(p.ok()) << p.status().message();
    ASSERT_EQ(p->size(), 12u);
    const std::vector<double> want = HandScene(mean, to_other);
    double sum = 0;
    for (size_t t = 0; t < 12; ++t) {
      EXPECT_NEAR((*p)[t], want[t], 1e-5) << "room type " << t + 1 << (to_other ? " (to other)" : " (dropped)");
      sum += (*p)[t];
    }
    EXPECT_NEAR(sum, 1.0, 1e-9);
  }
}

TEST(OnnxSceneModel, DefaultPreprocessingResizesTheViewTo224) {
  REQUIRE_PYTHON_ONNX();
  testing::ScratchDir dir("onnx_scene_224");
  const std::string model = MakeModel(python, dir, "scene", Json("scene", 224, 224, kSceneWeights, kSceneBias, true));
  testing::WriteText(dir.File("scene.tsv"), kSceneLabels);
  Result<OnnxSceneModel> m = OnnxSceneModel::Load(model, dir.File("scene.tsv"));
  ASSERT_TRUE(m.ok()) << m.status().message();
  // A one-colour 320x240 view: resizing keeps the colour, so the pooled input is that colour exactly.
  RenderedView view = QuadrantView(320, 240);
  for (size_t i = 0; i < view.rgb.data.size(); i += 3) view.rgb.data[i] = 90, view.rgb.data[i + 1] = 160, view.rgb.data[i + 2] = 30;
  Result<std::vector<double>> p = m->RoomTypeProbabilities(view);
  ASSERT_TRUE(p.ok()) << p.status().message();
  const std::vector<double> want = HandScene({90, 160, 30}, true);
  // 1e-3: OpenCV's GlobalAveragePool sums the 224 x 224 inputs in float32 (relative error ~1e-4 here).
  for (size_t t = 0; t < 12; ++t) EXPECT_NEAR((*p)[t], want[t], 1e-3) << "room type " << t + 1;
}

TEST(OnnxLabelMap, BadFilesNameFileLineAndGiveAHint) {
  struct Case {
    const char* text;
    LabelMapVocabulary vocabulary;
    const char* expected;  // Substring of the message.
  };
  const Case cases[] = {
      {"0\tbedroom\n1\tbedroomm\n", LabelMapVocabulary::kRoomType, "map.tsv:2: 'bedroomm' is not a room type"},
      {"0\twall\n# x\n\n3\tflor\n", LabelMapVocabulary::kNyu40, "map.tsv:4: 'flor' is not a NYU40 class"},
      {"a\twall\n", LabelMapVocabulary::kNyu40, "map.tsv:1: 'a' is not a network class index"},
      {"-1\twall\n", LabelMapVocabulary::kNyu40, "map.tsv:1: '-1' is not a network class index"},
      {"0\twall\n0\tfloor\n", LabelMapVocabulary::kNyu40, "map.tsv:2: network class 0 is already mapped on line 1"},
      {"0\n", LabelMapVocabulary::kNyu40, "map.tsv:1: expected NET_INDEX and a target"},
      {"0\t13\n", LabelMapVocabulary::kRoomType, "map.tsv:1: id 13 is out of range 0-12"},
      {"0\t41\n", LabelMapVocabulary::kNyu40, "map.tsv:1: id 41 is out of range 0-40"},
      {"# nothing\n\n", LabelMapVocabulary::kRoomType, "map.tsv: the label map lists no class"},
  };
  for (const Case& c : cases) {
    Result<OnnxLabelMap> m = ParseOnnxLabelMap(c.text, "map.tsv", c.vocabulary);
    ASSERT_FALSE(m.ok()) << c.text;
    EXPECT_EQ(m.status().code(), StatusCode::kInvalidInput);
    EXPECT_NE(m.status().message().find(c.expected), std::string::npos) << m.status().message();
    EXPECT_NE(m.status().message().find("(hint: "), std::string::npos) << m.status().message();
    EXPECT_EQ(m.status().message().find('\n'), std::string::npos) << m.status().message();
  }
  Result<OnnxLabelMap> missing = ReadOnnxLabelMap("/nonexistent/labels.tsv", LabelMapVocabulary::kNyu40);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.status().message().find("/nonexistent/labels.tsv: label map not found"), std::string::npos);
}

TEST(OnnxLabelMap, NamesResolveThroughTheSpecTables) {
  Result<OnnxLabelMap> rooms = ParseOnnxLabelMap(
      "0 /l/living_room\n1 Home_Office\n2 pantry\n3 hallway\n4 background\n5 -\n6 unknown\n7 /s/shower\n9 nursery\n",
      "rooms.tsv", LabelMapVocabulary::kRoomType);
  ASSERT_TRUE(rooms.ok()) << rooms.status().message();
  EXPECT_EQ(rooms->target_of_class, (std::vector<int>{8, 9, 11, 4, 12, -1, -1, 1, -1, 3}));
  EXPECT_EQ(rooms->listed, 9);
  Result<OnnxLabelMap> objects =
      ParseOnnxLabelMap("0 floor mat\n1 nightstand\n2 refrigerator\n3 otherprop\n4 Other_Furniture\n5 unlabeled\n6 33\n",
                        "objects.tsv", LabelMapVocabulary::kNyu40);
  ASSERT_TRUE(objects.ok()) << objects.status().message();
  EXPECT_EQ(objects->target_of_class, (std::vector<int>{20, 32, 24, 40, 39, -1, 33}));
}

TEST(OnnxModels, BadModelsFailAtLoadWithOneLine) {
  REQUIRE_PYTHON_ONNX();
  testing::ScratchDir dir("onnx_bad");
  testing::WriteText(dir.File("seg.tsv"), kSegLabels);
  testing::WriteText(dir.File("scene.tsv"), kSceneLabels);
  testing::WriteText(dir.File("garbage.onnx"), "this is not a protobuf");
  auto expect_error = [](const Status& st, const std::string& what) {
    EXPECT_EQ(st.code(), StatusCode::kInvalidInput);
    EXPECT_NE(st.message().find(what), std::string::npos) << st.message();
    EXPECT_EQ(st.message().find('\n'), std::string::npos) << st.message();
  };
  expect_error(OnnxObjectModel::Load(dir.File("missing.onnx"), dir.File("seg.tsv"), Nyu4Level()).status(),
               dir.File("missing.onnx") + ": ONNX model not found");
  expect_error(OnnxSceneModel::Load(dir.File("garbage.onnx"), dir.File("scene.tsv")).status(),
               dir.File("garbage.onnx") + ": not a model OpenCV DNN can read");
  // A scene network passed as the segmentation network, and the reverse.
  const std::string scene = MakeModel(python, dir, "scene", Json("scene", 224, 224, kSceneWeights, kSceneBias, false));
  const std::string seg = MakeModel(python, dir, "seg", Json("seg", 224, 224, kSegWeights, kSegBias, false));
  expect_error(OnnxObjectModel::Load(scene, dir.File("seg.tsv"), Nyu4Level()).status(), "must output [1,C,h,w], not [1,4]");
  expect_error(OnnxSceneModel::Load(seg, dir.File("scene.tsv")).status(), "must output one score per class");
  // A label map naming a class the network does not have.
  testing::WriteText(dir.File("big.tsv"), "0 wall\n7 floor\n");
  expect_error(OnnxObjectModel::Load(seg, dir.File("big.tsv"), Nyu4Level()).status(),
               dir.File("big.tsv") + ": lists network class 7 but " + seg + " outputs 5 classes");
  OnnxObjectModelOptions bad;
  bad.preprocessing.std[1] = 0;
  expect_error(OnnxObjectModel::Load(seg, dir.File("seg.tsv"), Nyu4Level(), bad).status(), "std[1] = 0");
}

}  // namespace
}  // namespace semvox

// ---- `semvox run` with ONNX flags: a bad model stops the run before anything is written ----

namespace semvox {
namespace {

struct CliOutcome {
  int exit_code;
  std::string stderr_text;
};

CliOutcome RunSemvox(const std::string& args, const testing::ScratchDir& dir) {
  const std::string err = dir.File("stderr.txt");
  const std::string cmd = std::string(SEMVOX_BINARY) + " " + args + " > /dev/null 2> " + err;
  const int rc = std::system(cmd.c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, testing::ReadText(err)};
}

void ExpectOneErrorLineAndNoOutput(const CliOutcome& o, const std::string& out, const std::string& what) {
  EXPECT_EQ(o.exit_code, 2) << o.stderr_text;
  EXPECT_EQ(std::count(o.stderr_text.begin(), o.stderr_text.end(), '\n'), 1) << o.stderr_text;
  EXPECT_EQ(o.stderr_text.rfind("semvox: error: ", 0), 0u) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find(what), std::string::npos) << o.stderr_text;
  EXPECT_FALSE(std::filesystem::exists(out)) << "the run wrote " << out;
}

TEST(OnnxCli, RunWithAMissingOrBadModelFailsWithOneLineAndWritesNothing) {
  testing::ScratchDir dir("onnx_cli");
  const std::string scene = std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply";
  const std::string out = dir.File("out");
  testing::WriteText(dir.File("scene.tsv"), kSceneLabels);
  testing::WriteText(dir.File("seg.tsv"), kSegLabels);
  testing::WriteText(dir.File("garbage.onnx"), "not a network");
  const std::string run = "run " + scene + " -o " + out + " ";
  ExpectOneErrorLineAndNoOutput(
      RunSemvox(run + "--scene-model " + dir.File("missing.onnx") + " --scene-labels " + dir.File("scene.tsv"), dir), out,
      dir.File("missing.onnx") + ": ONNX model not found");
  ExpectOneErrorLineAndNoOutput(
      RunSemvox(run + "--object-model " + dir.File("missing.onnx") + " --object-labels " + dir.File("seg.tsv"), dir), out,
      dir.File("missing.onnx") + ": ONNX model not found");
  ExpectOneErrorLineAndNoOutput(
      RunSemvox(run + "--object-model " + dir.File("garbage.onnx") + " --object-labels " + dir.File("seg.tsv"), dir), out,
      dir.File("garbage.onnx") + ": not a model OpenCV DNN can read");
  ExpectOneErrorLineAndNoOutput(RunSemvox(run + "--scene-model " + dir.File("garbage.onnx"), dir), out,
                                "--scene-model " + dir.File("garbage.onnx") + " needs --scene-labels");
  ExpectOneErrorLineAndNoOutput(
      RunSemvox(run + "--scene-model " + dir.File("garbage.onnx") + " --scene-labels x.tsv --scene-input 224", dir), out,
      "--scene-input 224: not an input size");
}

TEST(OnnxCli, RunWithABadLabelMapFailsWithOneLineAndWritesNothing) {
  REQUIRE_PYTHON_ONNX();
  testing::ScratchDir dir("onnx_cli_labels");
  const std::string model = MakeModel(python, dir, "seg", Json("seg", 224, 224, kSegWeights, kSegBias, false));
  testing::WriteText(dir.File("seg.tsv"), "0 wall\n1 flor\n");
  const std::string out = dir.File("out");
  ExpectOneErrorLineAndNoOutput(RunSemvox("run " + std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply -o " + out +
                                              " --object-model " + model + " --object-labels " + dir.File("seg.tsv"),
                                          dir),
                                out, dir.File("seg.tsv") + ":2: 'flor' is not a NYU40 class");
}

}  // namespace
}  // namespace semvox

// ---- pipeline/onnx_stage.h: the models the flags name ----

namespace semvox {
namespace {

TEST(OnnxStage, LoadsTheModelsTheFlagsNameWithTheirInputSizes) {
  REQUIRE_PYTHON_ONNX();
  testing::ScratchDir dir("onnx_stage");
  const int w = 32, h = 24;
  OnnxModelPaths args;
  args.object_model = MakeModel(python, dir, "seg", Json("seg", w, h, kSegWeights, kSegBias, false));
  args.object_labels = dir.File("seg.tsv");
  args.object_input_size = "32x24";
  args.scene_model = MakeModel(python, dir, "scene", Json("scene", 224, 224, kSceneWeights, kSceneBias, true));
  args.scene_labels = dir.File("scene.tsv");
  testing::WriteText(args.object_labels, kSegLabels);
  testing::WriteText(args.scene_labels, kSceneLabels);
  OnnxModels models;
  const Status st = LoadOnnxModels(args, &models);
  ASSERT_TRUE(st.ok()) << st.message();
  ASSERT_TRUE(models.scene.has_value() && models.object.has_value());
  EXPECT_EQ(models.object->level().name, "second");
  EXPECT_EQ(models.object->options().preprocessing.input_width, w);
  EXPECT_EQ(models.object->options().preprocessing.input_height, h);
  EXPECT_EQ(models.scene->options().preprocessing.input_width, 224);
  // Per-pixel argmax: the most probable second-level class of each quadrant's colour, by hand.
  Result<ImageF32> q = models.object->PixelProbabilities(QuadrantView(w, h));
  ASSERT_TRUE(q.ok()) << q.status().message();
  const Image<int32_t> labels = PixelArgmax(*q);
  const LabelLevel level = SecondLevel();
  const int nyu40_of_network_class[] = {nyu40::kWall, nyu40::kFloor, nyu40::kBed, 0, nyu40::kPillow};
  for (int quadrant = 0; quadrant < 4; ++quadrant) {
    const auto& c = kQuadrantColours[size_t(quadrant)];
    const std::vector<double> p = Softmax(kSegWeights, kSegBias, Normalised({double(c[0]), double(c[1]), double(c[2])}));
    int best = 0;
    for (int k = 1; k < 5; ++k)
      if (k != 3 && p[size_t(k)] > p[size_t(best)]) best = k;  // Class 3 maps to nothing.
    const int x = quadrant % 2 ? w - 1 : 0, y = quadrant / 2 ? h - 1 : 0;
    EXPECT_EQ(labels.at(x, y), level.class_of_nyu40[size_t(nyu40_of_network_class[best])]) << "quadrant " << quadrant;
  }
  // Flags in halves are errors naming the missing flag; no flags load nothing.
  OnnxModelPaths half;
  half.object_labels = args.object_labels;
  const Status missing = LoadOnnxModels(half, &models);
  EXPECT_NE(missing.message().find("--object-labels " + args.object_labels + " is given without --object-model"), std::string::npos)
      << missing.message();
  EXPECT_FALSE(models.any());
  ASSERT_TRUE(LoadOnnxModels(OnnxModelPaths{}, &models).ok());
  EXPECT_FALSE(models.any());
}

}  // namespace
}  // namespace semvox
