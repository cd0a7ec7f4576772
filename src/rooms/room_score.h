// Room segmentation scores as in Bormann et al., "Room Segmentation: Survey, Implementation, and
// Analysis", ICRA 2016, Sec. IV: recall is the mean over ground-truth rooms of the largest overlap with
// one predicted room divided by the ground-truth room's area; precision is the same from the predicted
// side (the largest overlap with one ground-truth room divided by the predicted room's area).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/image.h"

namespace semvox {

struct RoomScore {
  double recall = 0;     // In [0, 1]; 0 when there is no ground-truth room.
  double precision = 0;  // In [0, 1]; 0 when there is no predicted room.
  int num_ground_truth_rooms = 0;
  int num_predicted_rooms = 0;
};

// Both images hold room ids (0 = no room) and have the same size.
RoomScore ScoreRooms(const ImageU16& predicted, const ImageU16& ground_truth);

// Ground-truth rooms of an ipa_room_segmentation "_gt_segmentation" image: pixels brighter than
// `free_threshold` split into 8-connected components; components of `min_room_px` pixels or fewer are
// dropped (the benchmark's convention: > 250 and > 100 px).
ImageU16 GroundTruthRoomsFromImage(const Image<uint8_t>& grey, int free_threshold = 250, int min_room_px = 101);

}  // namespace semvox
