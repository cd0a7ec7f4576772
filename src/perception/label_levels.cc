#include "perception/label_levels.h"

#include "core/labels.h"

namespace semvox {

Image<int32_t> LabelLevel::Map(const Image<int32_t>& nyu40) const {
  Image<int32_t> out(nyu40.width, nyu40.height, 1, -1);
  for (size_t k = 0; k < nyu40.data.size(); ++k) {
    const int id = nyu40.data[k];
    out.data[k] = id >= 0 && id < int(class_of_nyu40.size()) ? class_of_nyu40[size_t(id)] : -1;
  }
  return out;
}

LabelLevel Nyu4Level() {
  LabelLevel level;
  level.name = "nyu4";
  level.class_names = {"ground", "structure", "furniture", "props"};
  level.class_of_nyu40.assign(kNumNyu40, -1);
  for (const LabelInfo& info : Nyu40Labels())
    if (info.id > 0 && info.nyu4_id >= 1 && info.nyu4_id <= 4) level.class_of_nyu40[size_t(info.id)] = info.nyu4_id - 1;
  return level;
}

LabelLevel SecondLevel() {
  using namespace nyu40;
  // ScanNet-20 (the NYU40 ids its benchmark scores) plus ceiling.
  const int kept[] = {kWall, kFloor, kCabinet, kBed, kChair, kSofa, kTable, kDoor, kWindow, kBookshelf, kPicture,
                      kCounter, kDesk, kCurtain, kRefrigerator, kShowerCurtain, kToilet, kSink, kBathtub,
                      kOtherFurniture, kCeiling};
  LabelLevel level;
  level.name = "second";
  level.class_of_nyu40.assign(kNumNyu40, -1);
  for (int id : kept) {
    level.class_of_nyu40[size_t(id)] = int(level.class_names.size());
    level.class_names.push_back(Nyu40Labels()[size_t(id)].name);
  }
  const int other = int(level.class_names.size());
  level.class_names.push_back("other");
  for (int id = 1; id < kNumNyu40; ++id)
    if (level.class_of_nyu40[size_t(id)] < 0) level.class_of_nyu40[size_t(id)] = other;
  return level;
}

}  // namespace semvox
