// One figure of an eval report, which may be absent (shared by the eval reports, eval/evaluate.h and the rest).
#pragma once

#include <string>

namespace semvox {

// A score that may be missing because its prediction file is.
struct Score {
  bool present = false;
  double value = 0.0;  // Fraction in [0, 1].
  std::string note;    // Why it is absent, or what it was computed on.
};

}  // namespace semvox
