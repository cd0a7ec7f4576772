// Labelled training and validation views from the apartment generator (library semvox_perception_train,
// which adds scenegen to semvox_perception; the classifier itself does not depend on the generator).
//
//   ForEachApartmentView(seed, TrainingViewsOptions{}, [&](const LabelledView& v) { ... });
//
// Each apartment is drawn with its seed, given the default scan artefacts (holes, unscanned ceiling:
// superpixels without depth), and seen from the middle of every room at eye height, looking around at
// `yaws_per_room` headings, slightly down. The ground truth of a pixel is the NYU40 `label` of the face it
// hits (0 where it hits nothing).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/status.h"
#include "render/view_renderer.h"

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

struct TrainingViewsOptions {
  int width = 320;                  // Pixels. >= 16.
  int height = 240;                 // Pixels. >= 16.
  double horizontal_fov_deg = 60;   // About a Kinect's, as in NYUv2. (0, 180).
  double eye_height_m = 1.6;        // Above the floor. > 0.
  double pitch_deg = -15;           // Negative looks down.
  int yaws_per_room = 4;            // Evenly spaced headings from the room's middle. >= 1.
  double min_hit_fraction = 0.5;    // Views seeing less surface than this are skipped. [0, 1].
  double min_mean_depth_m = 0.8;    // Views with a nearer mean depth (inside furniture) are skipped. >= 0.

  bool Check(std::string* error) const;
};

struct LabelledView {
  uint64_t seed = 0;
  int room_id = 0;
  int room_type = 0;                // room_types.tsv id.
  int heading = 0;                  // In [0, yaws_per_room).
  const RenderedView* view = nullptr;
  const Image<int32_t>* nyu40 = nullptr;  // Per pixel, 0 where nothing is hit.
};

// Calls `sink` for every kept view of apartment `seed`, in room then heading order. Stops at the first
// error `sink` returns.
Status ForEachApartmentView(uint64_t seed, const TrainingViewsOptions& options,
                            const std::function<Status(const LabelledView&)>& sink);

}  // namespace semvox
