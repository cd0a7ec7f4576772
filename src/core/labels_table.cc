// Label vocabularies, copied from ../shared/spec (nyu40_classes.tsv, room_types.tsv).
// Display colours are evenly spread hues; names and mappings are verbatim from the spec tables.
#include "core/labels.h"

namespace semvox {

const std::vector<LabelInfo>& Nyu40Labels() {
  static const std::vector<LabelInfo> kLabels = {
      {0, "unlabeled", 0, "unlabeled", 0, "unlabeled", {0, 0, 0}},
      {1, "wall", 12, "wall", 2, "structure", {49, 87, 178}},
      {2, "floor", 5, "floor", 1, "ground", {151, 242, 24}},
      {3, "cabinet", 6, "furniture", 3, "furniture", {178, 80, 166}},
      {4, "bed", 1, "bed", 3, "furniture", {67, 242, 213}},
      {5, "chair", 4, "chair", 3, "furniture", {178, 105, 18}},
      {6, "sofa", 9, "sofa", 3, "furniture", {142, 109, 242}},
      {7, "table", 10, "table", 3, "furniture", {55, 178, 49}},
      {8, "door", 12, "wall", 2, "structure", {242, 24, 97}},
      {9, "window", 13, "window", 2, "structure", {80, 142, 178}},
      {10, "bookshelf", 6, "furniture", 3, "furniture", {228, 242, 67}},
      {11, "picture", 8, "picture", 4, "props", {145, 18, 178}},
      {12, "counter", 6, "furniture", 2, "structure", {109, 242, 175}},
      {13, "blinds", 13, "window", 2, "structure", {178, 76, 49}},
      {14, "desk", 10, "table", 3, "furniture", {24, 43, 242}},
      {15, "shelves", 6, "furniture", 3, "furniture", {117, 178, 80}},
      {16, "curtain", 13, "window", 2, "structure", {242, 67, 184}},
      {17, "dresser", 6, "furniture", 3, "furniture", {18, 172, 178}},
      {18, "pillow", 7, "objects", 4, "props", {242, 209, 109}},
      {19, "mirror", 7, "objects", 4, "props", {108, 49, 178}},
      {20, "floor mat", 5, "floor", 4, "props", {24, 242, 60}},
      {21, "clothes", 7, "objects", 4, "props", {178, 80, 93}},
      {22, "ceiling", 3, "ceiling", 2, "structure", {67, 140, 242}},
      {23, "books", 2, "books", 4, "props", {132, 178, 18}},
      {24, "refridgerator", 6, "furniture", 3, "furniture", {242, 109, 242}},
      {25, "television", 11, "tv", 4, "props", {49, 178, 140}},
      {26, "paper", 7, "objects", 4, "props", {242, 114, 24}},
      {27, "towel", 7, "objects", 4, "props", {92, 80, 178}},
      {28, "shower curtain", 7, "objects", 2, "structure", {97, 242, 67}},
      {29, "box", 7, "objects", 4, "props", {178, 18, 92}},
      {30, "whiteboard", 7, "objects", 2, "structure", {109, 209, 242}},
      {31, "person", 7, "objects", 4, "props", {178, 173, 49}},
      {32, "night stand", 6, "furniture", 3, "furniture", {169, 24, 242}},
      {33, "toilet", 7, "objects", 3, "furniture", {80, 178, 117}},
      {34, "sink", 7, "objects", 4, "props", {242, 80, 67}},
      {35, "lamp", 7, "objects", 4, "props", {18, 52, 178}},
      {36, "bathtub", 7, "objects", 3, "furniture", {176, 242, 109}},
      {37, "bag", 7, "objects", 4, "props", {178, 49, 152}},
      {38, "otherstructure", 7, "objects", 2, "structure", {24, 242, 223}},
      {39, "otherfurniture", 6, "furniture", 3, "furniture", {178, 141, 80}},
      {40, "otherprop", 7, "objects", 4, "props", {124, 67, 242}},
  };
  return kLabels;
}

const std::vector<RoomTypeInfo>& RoomTypes() {
  static const std::vector<RoomTypeInfo> kTypes = {
      {0, "unknown"},
      {1, "bathroom"},
      {2, "bedroom"},
      {3, "childs_room"},
      {4, "corridor"},
      {5, "dining_room"},
      {6, "kitchen"},
      {7, "laundry"},
      {8, "living_room"},
      {9, "office"},
      {10, "staircase"},
      {11, "storage"},
      {12, "other"},
  };
  return kTypes;
}

}  // namespace semvox
