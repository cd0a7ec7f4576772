// Stateless 64-bit hashing for values that must depend only on their inputs (deterministic noise, seeds,
// fingerprints).
#pragma once

#include <cstdint>

namespace semvox {

// SplitMix64 (Steele et al. 2014): a stateless hash used where a value must depend only on its inputs
// (e.g. vertex noise keyed by position, so that coincident vertices move together).
inline uint64_t SplitMix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// A running hash h extended by v; the order of the values matters.
inline uint64_t HashCombine(uint64_t h, uint64_t v) { return SplitMix64(h ^ (v * 0xff51afd7ed558ccdULL)); }

}  // namespace semvox
