// Alias tables copied from ../shared/spec/room_types.tsv (columns name, seed_table_name, r2v_names,
// zind_names; the Matterport3D codes are single letters and left out) and nyu40_classes.tsv.
#include "core/label_aliases.h"

#include <algorithm>
#include <cctype>

#include "core/labels.h"

namespace semvox {
namespace {

struct Alias {
  const char* name;
  int id;
};

// room_types.tsv, row by row.
constexpr Alias kRoomTypeAliases[] = {
    {"unknown", 0},
    // 1 bathroom: seed "bathroom, shower"; r2v "bathroom,restroom"; zind "bathroom".
    {"bathroom", 1}, {"shower", 1}, {"restroom", 1},
    // 2 bedroom.
    {"bedroom", 2},
    // 3 childs_room: seed "childs room, nursery".
    {"childs room", 3}, {"nursery", 3},
    // 4 corridor: r2v "corridor"; zind "hallway,entryway".
    {"corridor", 4}, {"hallway", 4}, {"entryway", 4},
    // 5 dining_room.
    {"dining room", 5},
    // 6 kitchen: seed "kitchen, galley".
    {"kitchen", 6}, {"galley", 6},
    // 7 laundry: seed "laundromat"; r2v "washing_room"; zind "laundry".
    {"laundry", 7}, {"laundromat", 7}, {"washing room", 7},
    // 8 living_room.
    {"living room", 8},
    // 9 office: seed "office, home office".
    {"office", 9}, {"home office", 9},
    // 10 staircase: r2v "stairs".
    {"staircase", 10}, {"stairs", 10},
    // 11 storage: seed "storage room, closet, pantry"; r2v "closet,PS"; zind "closet,pantry".
    {"storage", 11}, {"storage room", 11}, {"closet", 11}, {"pantry", 11}, {"ps", 11},
    // 12 other: seed "background"; r2v "balcony"; zind "garage,bonus room".
    {"other", 12}, {"background", 12}, {"balcony", 12}, {"garage", 12}, {"bonus room", 12},
};

// NYU40 spelling variants beyond nyu40_classes.tsv's names (which keep the toolbox's "refridgerator").
constexpr Alias kNyu40Variants[] = {
    {"refrigerator", nyu40::kRefrigerator}, {"fridge", nyu40::kRefrigerator}, {"tv", nyu40::kTelevision},
    {"bookcase", nyu40::kBookshelf},
};

std::string WithoutSpaces(std::string s) {
  s.erase(std::remove(s.begin(), s.end(), ' '), s.end());
  return s;
}

}  // namespace

std::string NormalizeLabelName(const std::string& name) {
  std::string s = name;
  // Places365 category paths: "/b/bedroom", "/s/shower".
  if (s.size() > 3 && s[0] == '/' && s[2] == '/') s = s.substr(3);
  std::string out;
  for (char c : s) {
    char ch = char(std::tolower(static_cast<unsigned char>(c)));
    if (ch == '_' || ch == '-' || ch == '\t') ch = ' ';
    if (ch == ' ' && (out.empty() || out.back() == ' ')) continue;
    out.push_back(ch);
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

int RoomTypeIdByAlias(const std::string& name) {
  const std::string n = NormalizeLabelName(name);
  for (const Alias& a : kRoomTypeAliases)
    if (n == a.name) return a.id;
  return -1;
}

int Nyu40IdByAlias(const std::string& name) {
  const std::string n = WithoutSpaces(NormalizeLabelName(name));
  for (const LabelInfo& l : Nyu40Labels())
    if (n == WithoutSpaces(l.name)) return l.id;
  for (const Alias& a : kNyu40Variants)
    if (n == WithoutSpaces(a.name)) return a.id;
  return -1;
}

std::vector<std::string> RoomTypeAliases() {
  std::vector<std::string> names;
  for (const Alias& a : kRoomTypeAliases) names.push_back(a.name);
  return names;
}

}  // namespace semvox
