// Label vocabularies: NYU40 classes (the ids ScanNet and Matterport3D use) with their Eigen-13 and
// NYU-4 super-classes, and the 12 room types of the room-labelling paper (0 = unknown).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry.h"

namespace semvox {

struct LabelInfo {
  int id;                  // NYU40 id, 0 = unlabeled.
  const char* name;
  int eigen13_id;
  const char* eigen13_name;
  int nyu4_id;             // 1 ground, 2 structure, 3 furniture, 4 props.
  const char* nyu4_name;
  Rgb8 color;              // Display colour.
};

struct RoomTypeInfo {
  int id;  // 0 unknown, 1..12 as in room_types.tsv.
  const char* name;
};

inline constexpr int kNumNyu40 = 41;  // Ids 0..40.
inline constexpr int kNumRoomTypes = 13;  // Ids 0..12.

// Indexed by id (entry i has id i).
const std::vector<LabelInfo>& Nyu40Labels();
const std::vector<RoomTypeInfo>& RoomTypes();

// -1 when unknown.
int Nyu40IdByName(const std::string& name);
int RoomTypeIdByName(const std::string& name);

namespace nyu40 {
// Named ids used in code (values from nyu40_classes.tsv).
inline constexpr int kWall = 1, kFloor = 2, kCabinet = 3, kBed = 4, kChair = 5, kSofa = 6, kTable = 7, kDoor = 8,
                     kWindow = 9, kBookshelf = 10, kPicture = 11, kCounter = 12, kBlinds = 13, kDesk = 14,
                     kShelves = 15, kCurtain = 16, kDresser = 17, kPillow = 18, kMirror = 19, kFloorMat = 20,
                     kClothes = 21, kCeiling = 22, kBooks = 23, kRefrigerator = 24, kTelevision = 25, kPaper = 26,
                     kTowel = 27, kShowerCurtain = 28, kBox = 29, kWhiteboard = 30, kPerson = 31, kNightStand = 32,
                     kToilet = 33, kSink = 34, kLamp = 35, kBathtub = 36, kBag = 37, kOtherStructure = 38,
                     kOtherFurniture = 39, kOtherProp = 40;
}  // namespace nyu40

}  // namespace semvox
