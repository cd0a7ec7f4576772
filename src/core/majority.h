// The most frequent value of a list.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace semvox {

// The most frequent value of `values` (ties: the smallest); sorts them. `values` must not be empty.
template <typename T>
T Majority(std::vector<T>* values) {
  std::sort(values->begin(), values->end());
  T best = (*values)[0];
  size_t best_run = 0;
  for (size_t i = 0; i < values->size();) {
    size_t j = i;
    while (j < values->size() && (*values)[j] == (*values)[i]) ++j;
    if (j - i > best_run) best_run = j - i, best = (*values)[i];
    i = j;
  }
  return best;
}

}  // namespace semvox
