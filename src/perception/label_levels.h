// The label vocabularies of the per-view classifiers (NYU40 id -> class index), shared by the run-time
// classifiers and their training (perception/training_data.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/image.h"

namespace semvox {

// A label vocabulary the per-view classifier is trained on: NYU40 id -> class index (-1 = ignore).
struct LabelLevel {
  std::string name;
  std::vector<std::string> class_names;
  std::vector<int> class_of_nyu40;  // kNumNyu40 entries.
  int num_classes() const { return int(class_names.size()); }
  Image<int32_t> Map(const Image<int32_t>& nyu40) const;
};

// First level: NYU-4 (ground, structure, furniture, props), from labels.h.
LabelLevel Nyu4Level();
// Second level: the ScanNet-20 classes plus ceiling, each its own class, and "other" for every other
// labelled id (22 classes).
LabelLevel SecondLevel();

}  // namespace semvox
