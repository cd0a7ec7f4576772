// A random forest of classification trees (Breiman 2001), a candidate for the object-segment classifier
// (object_segments.h); `segments_bench --compare` scores it beside the shipped k-NN (docs/objects.md: better
// on generated validation segments, not on the real ScanNet studio, so not shipped).
//
//   Result<RandomForest> rf = RandomForest::Train(features, dims, labels, num_classes, RandomForestOptions{});
//   std::vector<double> p = rf->Probabilities(x);   // mean of the trees' leaf class shares, sums to one
//
// Each tree grows on a bootstrap sample of the rows; at every node it draws `features_per_split` of the
// dimensions and takes the threshold (midway between consecutive distinct values) with the lowest weighted
// Gini impurity, until a node is pure, holds fewer than 2 x `min_leaf` rows or reaches `max_depth`. Rows
// carry weights: with `balance_classes` each class weighs as much as every other in total, so that rare
// furniture (toilets, bins) is not outvoted by walls and tables.
//
// A k-NN over standardised hand features lets every dimension count as much as any other; a tree picks
// the few that separate two classes (a counter stands against a wall, a bar table does not) and ignores the
// rest.
//
// Deterministic: tree t draws from its own generator seeded by (seed, t), trees grow on both cores and are
// averaged in order; the same rows and options give the same model and the same probabilities.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/status.h"

namespace semvox {

struct RandomForestOptions {
  int trees = 100;               // >= 1.
  int features_per_split = 8;    // Dimensions drawn at each node; 0: round(sqrt(dims)). Capped at dims.
  int min_leaf = 1;              // Rows at least on each side of a split. >= 1.
  int max_depth = 30;            // >= 1.
  bool balance_classes = false;  // Weigh the rows so that every class present has the same total weight.
  // Probabilities below this are raised to it and the distribution renormalised, so that -log p stays
  // finite for a class no tree voted for. [0, 1 / num_classes).
  double probability_floor = 1e-3;
  uint64_t seed = 1;
  bool Check(std::string* error) const;
};

class RandomForest {
 public:
  // `features`: one row of `dims` values per observation (row-major); `labels`: one class in
  // [0, num_classes) per row. Fails on empty or inconsistent input or bad options.
  static Result<RandomForest> Train(std::span<const float> features, int dims, std::span<const int> labels, int num_classes,
                                    const RandomForestOptions& options);

  RandomForest(RandomForest&&) noexcept;
  RandomForest& operator=(RandomForest&&) noexcept;
  ~RandomForest();

  int dims() const;
  int num_classes() const;
  int num_trees() const;
  size_t num_nodes() const;  // Over all trees.

  // Mean over the trees of the class shares of the leaf `x` (dims() values) falls into, then the floor.
  std::vector<double> Probabilities(std::span<const float> x) const;

  // Text model file ("semvox_random_forest 1", sizes, options, then the nodes of every tree), written
  // atomically. Load checks every index and value and names the file and what is wrong.
  Status Save(const std::string& path) const;
  static Result<RandomForest> Load(const std::string& path);

 private:
  struct Impl;
  explicit RandomForest(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace semvox
