// Room-type evidence of one view: a k-NN (Eq. 4 again) over a global descriptor of the
// view: the histogram of its (predicted) object classes, colour and texture statistics and the spatial
// layout of its depth, giving a distribution over the 12 room types of room_types.tsv (index = id - 1).
// A view with too few object pixels holds too little evidence: all its mass goes to "other" (id 12).
#pragma once

#include <cstddef>  // core/image.h uses size_t without including it.
#include <string>
#include <vector>

#include "core/image.h"
#include "perception/knn_unary.h"
#include "render/view_renderer.h"

namespace semvox {

inline constexpr int kNumRoomTypeClasses = 12;  // room_types.tsv ids 1..12.
inline constexpr int kOtherRoomTypeIndex = 11;  // Id 12, "other".
// A view whose pixels are less than this fraction furniture or props holds too little evidence of its
// room type: its distribution goes to "other".
inline constexpr double kRoomMinObjectFraction = 0.02;
// A view's room-type evidence reaches this far from the camera on the floor plan, metres.
inline constexpr double kRoomViewRangeM = 8.0;
// Per class name: true for classes that say something about the room (not wall, floor, ceiling, window, door).
std::vector<bool> RoomObjectClasses(const std::vector<std::string>& class_names);

// num_classes class fractions over the pixels that hit a surface (classes < 0 ignored), then L, a, b mean
// and std over those pixels, mean |gradient of L| (texture), mean and std of depth (metres), fraction of
// pixels hit, and the fraction of hit pixels in the upper half of the image (layout).
int RoomDescriptorDims(int num_classes);
std::vector<float> RoomViewDescriptor(const RenderedView& view, const Image<int32_t>& classes, int num_classes);

// Fraction of hit pixels whose class is marked in `is_object_class` (furniture and props, not structure).
double ObjectPixelFraction(const RenderedView& view, const Image<int32_t>& classes, const std::vector<bool>& is_object_class);

// P(room type | view): `knn` over the descriptor (trained with labels id - 1), or "other" with probability 1
// when object_fraction < min_object_fraction.
std::vector<double> RoomTypeProbabilities(const KnnClassifier& knn, const std::vector<float>& descriptor,
                                          double object_fraction, double min_object_fraction);
// The same, and from the same search how unlike every training view the descriptor is: its mean distance to
// its k nearest training views (KnnClassifier::NeighbourDistance) over `familiar_distance` (the training views'
// own 0.99-quantile, KnnClassifier::TrainingNeighbourDistanceQuantile). NaN when the view goes to "other" for
// too few object pixels, or `familiar_distance` <= 0.
std::vector<double> RoomTypeProbabilities(const KnnClassifier& knn, const std::vector<float>& descriptor,
                                          double object_fraction, double min_object_fraction, double familiar_distance,
                                          double* unfamiliarity);

// A view unlike every training view says less about its room: its distribution mixes with the uniform one by
// lambda = clamp(unfamiliarity - 1, 0, 1), so that it counts fully up to the familiar distance and says nothing
// from twice that distance on. `p` keeps its sum. Returns lambda (0 for a NaN unfamiliarity).
double DiscountUnfamiliarRoomView(double unfamiliarity, std::vector<double>* p);

}  // namespace semvox
