#include "core/labels.h"

namespace semvox {

int Nyu40IdByName(const std::string& name) {
  for (const auto& l : Nyu40Labels())
    if (name == l.name) return l.id;
  return -1;
}

int RoomTypeIdByName(const std::string& name) {
  for (const auto& r : RoomTypes())
    if (name == r.name) return r.id;
  return -1;
}

}  // namespace semvox
