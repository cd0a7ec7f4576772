// JSON of the eval reports' scores, shared by evaluate.cc and box_eval.cc (private to semvox_eval: it
// includes nlohmann/json, which the public headers do not).
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "eval/box_eval.h"
#include "eval/confidence_eval.h"
#include "eval/evaluate.h"

namespace semvox {

// Six decimals, as every figure of eval.json.
inline double Round6(double v) { return std::round(v * 1e6) / 1e6; }

inline nlohmann::ordered_json ScoreJson(const Score& s) {
  nlohmann::ordered_json j;
  j["present"] = s.present;
  if (s.present) j["value"] = Round6(s.value);
  if (!s.note.empty()) j["note"] = s.note;
  return j;
}

// rooms_present, rooms and seconds of a real-scan report, appended to `j`.
inline void AddRoomsAndSecondsJson(const Score& rooms_present, const std::vector<RoomFound>& rooms,
                                   const std::vector<std::pair<std::string, double>>& seconds, nlohmann::ordered_json& j) {
  nlohmann::ordered_json rs = nlohmann::ordered_json::array();
  for (const RoomFound& r : rooms) rs.push_back({{"id", r.id}, {"type", r.type}, {"area_m2", Round6(r.area_m2)}});
  j["rooms_present"] = ScoreJson(rooms_present);
  j["rooms"] = rs;
  nlohmann::ordered_json sec = nlohmann::ordered_json::object();
  for (const auto& [stage, s] : seconds) sec[stage] = s;
  j["seconds"] = sec;
}

// A run's confidence scores (eval/confidence_eval.h) as JSON.
inline nlohmann::ordered_json ConfidenceJson(const ConfidenceScores& s) {
  nlohmann::ordered_json j;
  j["scored"] = s.scored;
  j["mean_confidence"] = ScoreJson(s.mean_confidence);
  j["accuracy"] = ScoreJson(s.accuracy);
  j["ece"] = ScoreJson(s.ece);
  j["auroc"] = ScoreJson(s.auroc);
  j["share_above_0.5"] = ScoreJson(s.share_above_05);
  j["accuracy_above_0.5"] = ScoreJson(s.accuracy_above_05);
  j["share_above_0.8"] = ScoreJson(s.share_above_08);
  j["accuracy_above_0.8"] = ScoreJson(s.accuracy_above_08);
  nlohmann::ordered_json bins = nlohmann::ordered_json::array();
  for (size_t b = 0; b < s.bins.size(); ++b)
    bins.push_back({{"from", double(b) / double(s.bins.size())}, {"to", double(b + 1) / double(s.bins.size())},
                    {"count", s.bins[b].count}, {"mean_confidence", Round6(s.bins[b].mean_confidence)},
                    {"accuracy", Round6(s.bins[b].accuracy)}});
  j["reliability"] = bins;
  return j;
}

// A score as a percentage, right-aligned in 8 characters ("absent" when absent).
inline std::string PercentCell(const Score& s) {
  char buf[32];
  if (s.present) std::snprintf(buf, sizeof buf, "%6.1f %%", 100.0 * s.value);
  else std::snprintf(buf, sizeof buf, "%8s", "absent");
  return buf;
}

// One "name  value  (note)" line of the real-scan eval tables.
inline void AppendScoreRow(std::ostream& os, const char* name, const Score& s) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "  %-26s%10s", name, PercentCell(s).c_str());
  os << buf;
  if (!s.note.empty()) os << "   (" << s.note << ")";
  os << "\n";
}

}  // namespace semvox
