// Where the per-view classifiers' views stand and what they must see: the training views
// (perception/training_data.h, TrainingViewsOptions' defaults) and the pipeline's classification views
// (pipeline/semantic_evidence.h) share these, so that the run classifies views like those it learned on.
#pragma once

namespace semvox {

struct ClassifierViews {
  static constexpr double kHorizontalFovDeg = 60;   // About a Kinect's, as in NYUv2.
  static constexpr double kEyeHeightM = 1.6;        // Above the floor.
  static constexpr double kPitchDeg = -15;          // Negative looks down.
  static constexpr double kMinHitFraction = 0.5;    // Views seeing less surface than this are skipped.
  static constexpr double kMinMeanDepthM = 0.8;     // Views with a nearer mean depth (inside furniture) are skipped.
};

}  // namespace semvox
