// JSON of the eval reports' scores, shared by evaluate.cc and box_eval.cc (private to semvox_eval: it
// includes nlohmann/json, which the public headers do not).
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>

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

}  // namespace semvox
