// Room types from a room's shape, learnt from real floor plans (library semvox_rooms).
//
//   room-id raster --MeasureRoomShapes--> RoomShape per room (area, aspect, fill, width, connections)
//   R2V plans 0-299 --TrainRoomShapeModel--> RoomShapeModel (models/room_shape.json)
//   RoomShapeModel + RoomShape --LogLikelihoodRatios--> per type: log p(shape | type) - log mean_k p(shape | k)
//
// A 3 m² room is a bathroom, a WC or a closet far more often than a living room, a 1.2 m wide room is a
// corridor, a 25 m² room with four neighbours a living room: what real plans say about shapes, which neither
// the views nor the objects of a sparse scan may show. The model is a Gaussian per room type over the shape
// vector (log area, log aspect, log width, log area share), fitted to the rooms of real R2V plans
// (Liu et al., ICCV 2017). Types with too few rooms in the plans (dining rooms, offices and children's rooms
// are not labelled in R2V) take the ratio of a stand-in type of like size (a child's room or an office
// that of a bedroom, a dining room that of a living room), so that the shape does not favour the modelled
// types over them; a type with neither gets 0. Kitchens and dining rooms are often part of an open-plan
// living room, and the region the CRF sees then has the living room's shape: their ratio is at least the
// living room's, so the shape never stops the CRF from splitting a kitchen off a large open space. The room-type stage weighs the
// ratios into each room's marginals by Bayes' rule (room_type_crf.h, RoomTypeCrfOptions::shape_weight).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/status.h"

namespace semvox {

// Every feature a room's shape offers (RoomShape::Vector); a model uses the ones it names (RoomShapeModel::features).
inline constexpr int kRoomShapeFeatures = 6;
inline constexpr int kRoomShapeTypes = 12;  // room_types.tsv ids 1..12; index = id - 1.

struct RoomShape {
  double area_m2 = 0;      // Pixels x pixel area.
  double aspect = 1;       // Length / width of the bounding box along the room's principal axes, >= 1.
  double fill = 1;         // Area / that box's area, (0, 1].
  double width_m = 0;      // Twice the largest distance from a room pixel to the room's edge (the widest
                           // inscribed square's side): a corridor is long and narrow.
  int connections = 0;     // Other rooms it opens into (through a door or an opening).
  std::vector<int> neighbours;  // Their ids.
  double area_share = 1;   // Area / the area of all rooms of the raster (plan or scan), (0, 1].
  double exterior_share = 0;  // Share of the room's edge pixels with no pixel of another room within
                              // kExteriorReachM: the edge that faces the outside (or unscanned space).
  // All features, in the order of RoomShapeFeatureNames(): log area, log aspect, log width, log area share,
  // log(1 + connections), exterior share. The fill is reported but is no feature: plan rooms are near-perfect
  // rectangles (fill 0.99 +- 0.02 for bathrooms) while a scanned room's outline is ragged with furniture and
  // unobserved cells.
  std::array<double, kRoomShapeFeatures> Vector() const;
};

// Shapes of rooms 1..num_rooms of a room-id raster (0 = no room) with square pixels of `resolution_m`.
// Connections: rooms whose pixels are 4-neighbours, unless `connections` is given (one set of neighbour ids
// per room, index = id), which is then used as it is.
std::vector<RoomShape> MeasureRoomShapes(const ImageU16& ids, int num_rooms, double resolution_m,
                                     const std::vector<std::vector<int>>* connections = nullptr);

// Names of RoomShape::Vector()'s entries, as the model files give them, and the index of one (-1: unknown).
const std::array<const char*, kRoomShapeFeatures>& RoomShapeFeatureNames();
int RoomShapeFeatureIndex(const std::string& name);

// How far across a wall another room may lie for an edge pixel to count as interior (RoomShape::exterior_share).
inline constexpr double kExteriorReachM = 0.6;

struct RoomShapeModel {
  // Indices into RoomShape::Vector() of the features the model uses (the first four until 2026-12-04).
  std::vector<int> features = {0, 1, 2, 3};
  struct TypeModel {
    int rooms = 0;                            // Training rooms; 0: not modelled.
    std::vector<double> mean;                 // Per used feature.
    std::vector<double> inverse_covariance;   // Row-major, used x used.
    double log_det_covariance = 0;
    int proxy_type_id = 0;  // Not modelled: the type whose ratio it takes (0: none).
  };
  std::array<TypeModel, kRoomShapeTypes> types{};
  // Which types neighbour which (a door or an opening between them): log P(a, b) / (P(a) P(b)) over the
  // neighbouring room pairs of the plans, [a][b] with index = id - 1, clipped to [-kMaxAdjacency,
  // kMaxAdjacency]; all 0 when not learnt (a model file from before 2026-12-04).
  std::array<std::array<double, kRoomShapeTypes>, kRoomShapeTypes> adjacency{};
  double max_ratio = 3.0;   // Ratios are clipped to [-min_ratio, max_ratio] (natural log).
  double min_ratio = 5.0;
  std::string provenance;
};

struct RoomShapeSample {
  int type_id = 0;  // room_types.tsv id 1..12.
  RoomShape shape;
  std::vector<int> neighbours;  // Indices (into the sample list) of the typed rooms it opens into.
};

inline constexpr double kMaxAdjacency = 2.0;

// The adjacency log ratios of the samples' neighbour pairs (each unordered pair once per direction), with
// `pseudo_count` added to every pair of modelled types; types without rooms take the stand-ins of
// TrainRoomShapeModel; a type beside itself is never below 0 (a segmentation may cut one room in two).
std::array<std::array<double, kRoomShapeTypes>, kRoomShapeTypes> TrainRoomAdjacency(const std::vector<RoomShapeSample>& samples,
                                                                                     double pseudo_count = 1.0);

// One neighbour's part of the adjacency message: message[y] += weight * sum_t neighbour_share[t] adjacency[y][t].
void AddAdjacencyMessage(const std::array<std::array<double, kRoomShapeTypes>, kRoomShapeTypes>& adjacency,
                         const std::array<double, kRoomShapeTypes>& neighbour_share, double weight,
                         std::array<double, kRoomShapeTypes>* message);

// Room-level mean field of the adjacency term: room r's types have log evidence `log_evidence[r]` (any
// offset), rooms `neighbours[r]` (indices) are next to it; returns per room the message
// m_r(y) = weight * sum over neighbours s of sum_t q_s(t) adjacency[y][t], where q_s ∝ exp(log_evidence[s] + m_s)
// after `iterations` parallel updates (damped by half). Rooms with no neighbour get 0.
std::vector<std::array<double, kRoomShapeTypes>> AdjacencyMessages(const RoomShapeModel& model,
                                                                   const std::vector<std::array<double, kRoomShapeTypes>>& log_evidence,
                                                                   const std::vector<std::vector<int>>& neighbours, double weight,
                                                                   int iterations = 20);

// One Gaussian per type with at least `min_rooms` samples over the features `features` (indices into
// RoomShape::Vector()); covariances get `ridge` on the diagonal. Stand-ins: childs_room and office -> bedroom,
// dining_room -> living_room.
RoomShapeModel TrainRoomShapeModel(const std::vector<RoomShapeSample>& samples, int min_rooms = 15, double ridge = 0.01,
                                   const std::vector<int>& features = {0, 1, 2, 3});

// Per type (index = id - 1): log p(shape | type) - log of the mean over the modelled types, clipped; 0 for
// types the model does not cover.
// `open_plan` = false leaves out the open-plan rule (the model's own argmax, for its validation report).
std::array<double, kRoomShapeTypes> LogLikelihoodRatios(const RoomShapeModel& model, const RoomShape& shape, bool open_plan = true);

std::string RoomShapeModelToJson(const RoomShapeModel& model);
Status SaveRoomShapeModel(const RoomShapeModel& model, const std::string& path);
Result<RoomShapeModel> LoadRoomShapeModel(const std::string& path);

}  // namespace semvox
