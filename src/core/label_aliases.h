// Names other datasets and networks use for the semvox vocabularies, resolved to room_types.tsv ids and
// NYU40 ids: the room_types.tsv columns seed_table_name (the Places365 scene names of the room-labelling
// paper), r2v_names and zind_names, and the NYU40 names with a few spelling variants. Used by label-map
// files (perception/onnx_models.h) and importers.
//
//   NormalizeLabelName("/l/living_room")  -> "living room"
//   RoomTypeIdByAlias("/g/galley")        -> 6 (kitchen)
//   Nyu40IdByAlias("refrigerator")        -> 24
#pragma once

#include <string>
#include <vector>

namespace semvox {

// Lower case; a leading Places365 "/x/" prefix removed; '_' and '-' read as spaces; runs of spaces
// collapsed and trimmed.
std::string NormalizeLabelName(const std::string& name);

// A room_types.tsv id in 1..12 for a room-type name or alias (any column of room_types.tsv but the
// Matterport3D codes), compared after NormalizeLabelName; -1 when unknown. "unknown" gives 0.
int RoomTypeIdByAlias(const std::string& name);

// A NYU40 id in 0..40 for a NYU40 name (nyu40_classes.tsv) or spelling variant, compared after
// NormalizeLabelName with spaces ignored ("night stand" = "nightstand", "otherprop" = "other prop");
// -1 when unknown. "unlabeled" gives 0.
int Nyu40IdByAlias(const std::string& name);

// Every accepted room-type name and alias, for hints.
std::vector<std::string> RoomTypeAliases();

}  // namespace semvox
