// Fine labels for the "other" class: which NYU40 object the voxels of a segment that came out "other" are
// (library semvox_objects).
//
//   Result<OtherLabeller> fine = OtherLabeller::Load("models/other_labels.knn");
//   std::vector<uint32_t> other = ...;  // voxels of `segments.segments[i]` the Voxel-CRF labelled "other"
//   int id = fine->Label(OtherFeatures(grid, segments, segments.segments[i], other));  // e.g. nyu40::kLamp
//
// The per-view classifiers, the object segments and the Voxel-CRF know the ScanNet-20 classes, ceiling and
// one class "other" for the remaining NYU40 ids (pillow, box, bag, lamp, television, night stand, dresser,
// books, clothes, paper, ...; perception/label_levels.h). One id had to be written for all of them, so a
// lamp, a box and a bag all came out "pillow". Here the voxels of one object segment (object_segments.h)
// that came out "other" are described by their own shape in the canonical frame (the segment features of
// those voxels alone), how they sit in their segment (the segment's top above theirs, their share of it) and
// what holds them (the segment's top surface height and footprint): a pillow lies on a bed top, a lamp
// stands tall and thin on a night stand, a box or a bag on the floor. A k-NN (standardised features, the plain
// majority of the 10 nearest) trained on the randomised generated scans (objects/segment_training.h) gives
// the NYU40 id among those "other" covers. Eq. 4 of the MST-CRF paper (each class's votes over its training
// frequency) was measured first and is not used: it names rare ids where the common ones are right (a
// generated living room's 304 "pillow" voxels became night stands, and the room a bedroom), and the plain vote
// is as good or better on every validation figure (docs/objects.md).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/status.h"
#include "core/voxel_grid.h"
#include "objects/object_segments.h"

namespace semvox {

class KnnClassifier;

// The segment features of the "other" voxels alone (kSegNeighbourRise: the segment's top above theirs),
// then these.
enum OtherFeature : int {
  kOtherShare = kNumSegmentFeatures,  // Their voxels / the segment's.
  kOtherSupportTop,                   // The segment's top-surface height (kSegTopSurface), metres.
  kOtherSegmentFootprint,             // The segment's footprint (kSegFootprint), m².
  kNumOtherFeatures
};
using OtherFeatureVector = std::array<float, kNumOtherFeatures>;

// `other`: voxels of `segment` (grid indices, non-empty), `segments` the SegmentObjects result it is from.
OtherFeatureVector OtherFeatures(const VoxelGrid& grid, const SegmentationResult& segments, const ObjectSegment& segment,
                                 const std::vector<uint32_t>& other);

// True for the NYU40 ids the second-level class "other" covers (label_levels.h's SecondLevel()).
bool IsOtherNyu40(int id);

class OtherLabeller {
 public:
  // A k-NN over kNumOtherFeatures with one class per NYU40 id (kNumNyu40 classes; only "other" ids have rows).
  explicit OtherLabeller(KnnClassifier knn);
  OtherLabeller(OtherLabeller&&) noexcept;
  OtherLabeller& operator=(OtherLabeller&&) noexcept;
  ~OtherLabeller();

  // The "other" NYU40 id most of the k nearest training rows hold (ties: the lower id; otherprop when none).
  int Label(std::span<const float> features) const;
  const KnnClassifier& knn() const { return *knn_; }

  Status Save(const std::string& path) const;  // Atomic.
  // Fails with one line naming the file when it is not such a model (dimensions or class count).
  static Result<OtherLabeller> Load(const std::string& path);

 private:
  std::unique_ptr<KnnClassifier> knn_;
};

// Fewer "other" voxels in a segment than this say too little of a shape: training skips such segments and
// `semvox run` leaves their voxels the Voxel-CRF model's one "other" id.
inline constexpr int kOtherMinVoxels = 4;

// The model's file name in a models directory.
inline constexpr const char* kOtherLabellerFile = "other_labels.knn";

// Items on top of a segment: its voxels above its top surface (the layer kSegTopSurface names), in
// 26-connected groups of at least `min_voxels` (grid indices, ascending; groups in order of first voxel). A
// pillow or clothes on a bed, books or paper on a table, a sink or a hob on a counter, a lamp on a night stand,
// a television on a cabinet; and parts of the furniture itself: a headboard, a sofa's back, a desk's shelf.
std::vector<std::vector<uint32_t>> ItemsOnTop(const VoxelGrid& grid, const SegmentationResult& segments, const ObjectSegment& segment,
                                              int min_voxels);

// Which items on top are objects of their own: a k-NN over OtherFeatures of the group (class 0: part of the
// segment's own object; else the item's NYU40 id), decided by the plain majority of the k nearest training
// groups (ties: 0). Eq. 4's class-frequency normalisation is not used here: it would favour the rare item
// classes over "part of the furniture", the most frequent answer. A group unlike every training group (its
// mean distance to the k nearest over the 0.99-quantile of the training groups' own, as
// SegmentClassifier::Unfamiliarity) stays part of its furniture: on the sparse ScanNet studio one "bed"
// segment spans the bed, the sofa and the floor between them, and what lies on it is no object the
// training scenes show.
class ItemLabeller {
 public:
  explicit ItemLabeller(KnnClassifier knn);
  ItemLabeller(ItemLabeller&&) noexcept;
  ItemLabeller& operator=(ItemLabeller&&) noexcept;
  ~ItemLabeller();

  // 0 (part of the furniture, or unfamiliar) or an NYU40 id.
  int Label(std::span<const float> features) const;
  const KnnClassifier& knn() const { return *knn_; }
  double familiar_distance() const { return familiar_distance_; }

  Status Save(const std::string& path) const;  // Atomic.
  static Result<ItemLabeller> Load(const std::string& path);

 private:
  std::unique_ptr<KnnClassifier> knn_;
  double familiar_distance_;
};

inline constexpr const char* kItemLabellerFile = "item_labels.knn";

}  // namespace semvox
