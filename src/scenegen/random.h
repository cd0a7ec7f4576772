// A seeded random number generator whose output is the same on every platform and standard library.
//
// std::mt19937_64's raw output is fixed by the C++ standard, but std::uniform_real_distribution and
// friends are not, so the generator draws through the distributions below and never through <random>'s.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "core/hash.h"

namespace semvox {

class Rng {
 public:
  explicit Rng(uint64_t seed) : engine_(seed) {}

  uint64_t Next() { return engine_(); }
  // Uniform in [0, 1) with 53 random bits.
  double Uniform01() { return double(Next() >> 11) * 0x1.0p-53; }
  // Uniform in [lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform01(); }
  // Uniform integer in [lo, hi] (inclusive), by rejection (no modulo bias).
  int UniformInt(int lo, int hi) {
    const uint64_t range = uint64_t(int64_t(hi) - lo) + 1;
    const uint64_t limit = UINT64_MAX - UINT64_MAX % range;
    uint64_t x;
    do x = Next();
    while (x >= limit);
    return lo + int(x % range);
  }
  bool Bernoulli(double p) { return Uniform01() < p; }
  // Standard normal by the Box-Muller transform.
  double Normal(double mean = 0.0, double sigma = 1.0) {
    const double u1 = 1.0 - Uniform01();  // (0, 1]
    const double u2 = Uniform01();
    return mean + sigma * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
  template <typename T>
  const T& Pick(const std::vector<T>& v) { return v[size_t(UniformInt(0, int(v.size()) - 1))]; }
  template <typename T>
  void Shuffle(std::vector<T>* v) {  // Fisher-Yates.
    for (int i = int(v->size()) - 1; i > 0; --i) std::swap((*v)[size_t(i)], (*v)[size_t(UniformInt(0, i))]);
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace semvox
