// Room-type CRF: potentials' names, object groups, the model file (room_type_crf.h).
#include "rooms/room_type_crf.h"

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>
#include <unordered_map>

#include "core/file_util.h"
#include "core/labels.h"
#include "rooms/room_type_crf_internal.h"

namespace semvox {

using namespace room_type_internal;

int ObjectGroupOf(int nyu40) {
  switch (nyu40) {
    case 4: case 6:  // bed, sofa: group 4.
      return 3;
    case 12: case 24: case 28: case 33: case 34: case 36:  // counter, refrigerator, shower curtain, toilet, sink, bathtub.
      return 2;
    case 3: case 5: case 7: case 10: case 14: case 15: case 17: case 32: case 39:  // cabinet, chair, table, bookshelf,
      return 0;                                                                     // desk, shelves, dresser, night stand, otherfurniture.
    case 11: case 18: case 19: case 20: case 21: case 23: case 25: case 26: case 27: case 29: case 30: case 35: case 37:
    case 40:  // picture, pillow, mirror, floor mat, clothes, books, tv, paper, towel, box, whiteboard, lamp, bag, otherprop.
      return 1;
    default:  // unlabelled, wall, floor, door, window, blinds, curtain, ceiling, person, otherstructure.
      return -1;
  }
}

const char* ScenePotentialName(ScenePotential s) { return s == ScenePotential::kCnn ? "cnn" : "conf"; }
const char* HomogeneityPotentialName(HomogeneityPotential h) {
  return h == HomogeneityPotential::kNone ? "none" : h == HomogeneityPotential::kStatistics ? "stat" : "gauss";
}
bool ParseScenePotential(const std::string& name, ScenePotential* out) {
  if (name == "cnn") return *out = ScenePotential::kCnn, true;
  if (name == "conf") return *out = ScenePotential::kConfusion, true;
  return false;
}
bool ParseHomogeneityPotential(const std::string& name, HomogeneityPotential* out) {
  if (name == "none") return *out = HomogeneityPotential::kNone, true;
  if (name == "stat") return *out = HomogeneityPotential::kStatistics, true;
  if (name == "gauss") return *out = HomogeneityPotential::kGaussian, true;
  return false;
}

std::string RoomTypeVariant::Name() const {
  return std::string(ScenePotentialName(scene)) + "+" + HomogeneityPotentialName(homogeneity) + (objects ? "+obj" : "");
}

RoomTypeWeights RoomTypeModel::WeightsFor(const RoomTypeVariant& variant) const {
  for (const auto& [name, w] : weights)
    if (name == variant.Name()) return w;
  return RoomTypeWeights{};
}

void RoomTypeModel::SetWeights(const RoomTypeVariant& variant, const RoomTypeWeights& w) {
  for (auto& [name, old] : weights)
    if (name == variant.Name()) return void(old = w);
  weights.emplace_back(variant.Name(), w);
}

RoomTypeModel RoomTypeModel::Uninformative() {
  RoomTypeModel m;
  for (int l = 0; l < kRoomTypeLabels; ++l)
    for (int y = 0; y < kRoomTypeLabels; ++y) m.confusion[size_t(l)][size_t(y)] = l == y ? 1 : 0;
  m.object_type.assign(kNumNyu40, Uniform());
  m.hom_log_prob.assign(12, {std::log(0.5), std::log(0.5), std::log(0.5), std::log(0.5)});
  m.provenance = "uninformative";
  return m;
}

std::string RoomTypeModelToJson(const RoomTypeModel& m) {
  using nlohmann::ordered_json;
  ordered_json j;
  j["format"] = "semvox room-type CRF model 1";
  j["provenance"] = m.provenance;
  j["confusion_true_given_view_argmax"] = m.confusion;
  j["object_type_given_object"] = m.object_type;
  j["hom_bin_m"] = m.hom_bin_m;
  j["hom_log_prob"] = m.hom_log_prob;
  j["no_fixture_log_prob"] = m.no_fixture_log_prob;
  ordered_json w = ordered_json::object();
  for (const auto& [name, x] : m.weights)
    w[name] = {{"scene", x.scene}, {"objects", x.objects}, {"homogeneity", x.homogeneity}};
  j["weights"] = w;
  j["dense_crf"] = {{"w_appearance", m.dense.w_appearance}, {"theta_alpha_m", m.dense.theta_alpha_m},
                    {"w_smooth", m.dense.w_smooth}, {"theta_gamma_m", m.dense.theta_gamma_m}};
  return j.dump(1) + "\n";
}

Status SaveRoomTypeModel(const RoomTypeModel& model, const std::string& path) {
  return WriteFileAtomic(path, RoomTypeModelToJson(model));
}

Result<RoomTypeModel> LoadRoomTypeModel(const std::string& path) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  RoomTypeModel m;
  try {
    const nlohmann::json j = nlohmann::json::parse(bytes);
    if (j.at("format").get<std::string>() != "semvox room-type CRF model 1") throw std::runtime_error("unknown format");
    m.provenance = j.value("provenance", "");
    m.confusion = j.at("confusion_true_given_view_argmax").get<decltype(m.confusion)>();
    m.object_type = j.at("object_type_given_object").get<decltype(m.object_type)>();
    m.hom_bin_m = j.at("hom_bin_m").get<double>();
    m.hom_log_prob = j.at("hom_log_prob").get<decltype(m.hom_log_prob)>();
    if (j.contains("no_fixture_log_prob")) m.no_fixture_log_prob = j.at("no_fixture_log_prob").get<decltype(m.no_fixture_log_prob)>();
    for (const auto& [name, x] : j.at("weights").items()) {
      RoomTypeWeights w;
      w.scene = x.at("scene").get<double>();
      w.objects = x.at("objects").get<decltype(w.objects)>();
      w.homogeneity = x.at("homogeneity").get<double>();
      m.weights.emplace_back(name, w);
    }
    const auto& d = j.at("dense_crf");
    m.dense = {d.at("w_appearance").get<double>(), d.at("theta_alpha_m").get<double>(), d.at("w_smooth").get<double>(),
               d.at("theta_gamma_m").get<double>()};
    if (m.object_type.size() != size_t(kNumNyu40) || m.hom_log_prob.empty() || !(m.hom_bin_m > 0))
      throw std::runtime_error("object table needs 41 rows, homogeneity table at least one bin");
  } catch (const std::exception& e) {
    return Status::InvalidInput(FileError(path, std::string("not a room-type CRF model: ") + e.what(),
                                          "write it with `semvox train`"));
  }
  return m;
}

bool RoomTypeCrfOptions::Check(std::string* error) const { return CheckOptions(*this, Options(), error); }

}  // namespace semvox
