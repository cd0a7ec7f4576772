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
#include "perception/classifier_views.h"
#include "perception/label_levels.h"
#include "perception/view_augmentation.h"
#include "render/view_renderer.h"

namespace semvox {

// How training apartments look. kFlat: the generator's own flat per-object colours on the scanned mesh,
// views from each room's middle (the style every model was trained on before randomisation). kRandomised:
// domain randomisation (view_augmentation.h) on a mesh or a simulated fused cloud with random point
// spacing, holes and missing ceiling, seen from jittered positions, heights, headings and pitches.
enum class TrainingStyle { kFlat, kRandomised };
const char* TrainingStyleName(TrainingStyle style);
bool ParseTrainingStyle(const std::string& name, TrainingStyle* style);

struct TrainingViewsOptions {
  TrainingStyle style = TrainingStyle::kFlat;
  int width = 320;                  // Pixels. >= 16.
  int height = 240;                 // Pixels. >= 16.
  double horizontal_fov_deg = ClassifierViews::kHorizontalFovDeg;  // About a Kinect's, as in NYUv2. (0, 180).
  double eye_height_m = ClassifierViews::kEyeHeightM;              // Above the floor. > 0.
  double pitch_deg = ClassifierViews::kPitchDeg;                   // Negative looks down.
  int yaws_per_room = 4;            // Evenly spaced headings from the room's middle. >= 1.
  double min_hit_fraction = ClassifierViews::kMinHitFraction;      // Views seeing less surface than this are skipped. [0, 1].
  double min_mean_depth_m = ClassifierViews::kMinMeanDepthM;       // Views with a nearer mean depth (inside furniture) are skipped. >= 0.
  // kRandomised only:
  double cloud_probability = 0.5;        // An apartment is delivered as a simulated fused cloud. [0, 1].
  double min_point_spacing_m = 0.015;    // Fusion grid of the cloud drawn in [min, max], metres. > 0.
  double max_point_spacing_m = 0.06;
  double position_jitter = 0.35;         // Eye moved from the room's middle by up to this share of the half-extents. [0, 1).
  double eye_height_jitter_m = 0.25;     // Eye height drawn in eye_height_m +- this, metres. >= 0.
  double pitch_jitter_deg = 10;          // Pitch drawn in pitch_deg +- this, degrees. >= 0.
  ViewAugmentationOptions augmentation;

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

struct Apartment;  // scenegen/apartment.h

// The scan of a generated apartment as the training views see it: kFlat, the mesh with the default scan
// artefacts; kRandomised, with `cloud_probability` a simulated fused cloud (random point spacing, no
// normals, holes, the ceiling missing in patches or wholly), else the mesh with random artefacts. Faces or
// points keep their `label`, `instance` and `room` attributes. Deterministic in `seed`.
Result<Scene> MakeTrainingScan(const Apartment& apartment, uint64_t seed, const TrainingViewsOptions& options);

// Calls `sink` for every kept view of apartment `seed`, in room then heading order. Stops at the first
// error `sink` returns.
Status ForEachApartmentView(uint64_t seed, const TrainingViewsOptions& options,
                            const std::function<Status(const LabelledView&)>& sink);
// The same for a given apartment (one built on a real plan, say); `seed` draws the scan and the views and is
// the views' `seed`. A room whose box middle is not on its own floor (an L-shaped room of a plan) is seen from
// the point of its floor nearest that middle at least 0.3 m from its edge (else its floor point nearest it).
Status ForEachViewOfApartment(const Apartment& apartment, uint64_t seed, const TrainingViewsOptions& options,
                              const std::function<Status(const LabelledView&)>& sink);

}  // namespace semvox
