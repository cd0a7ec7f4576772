// A strict PLY reader and a binary PLY writer (Turk's format: ascii, binary little / big endian).
//
// The reader keeps every element and property, so per-face attributes such as the generator's
// `label`, `instance` and `room` survive (assimp drops them). It rejects what would crash or hang a
// naive reader: missing magic, unknown formats or types, element counts larger than the file can hold,
// truncated bodies, list lengths beyond a sane bound.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/status.h"

namespace semvox {

enum class PlyType : uint8_t { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

int PlyTypeSize(PlyType t);
const char* PlyTypeName(PlyType t);

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;  // Item type for lists.
  bool is_list = false;
  PlyType count_type = PlyType::kUInt8;  // Lists only.
  // Scalars: one value per element. Lists: offsets (count + 1) into list_values.
  std::vector<double> values;
  std::vector<uint32_t> list_offsets;
  std::vector<double> list_values;
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> properties;
  const PlyProperty* Find(const std::string& property) const;
};

struct PlyData {
  std::vector<PlyElement> elements;
  std::vector<std::string> comments;
  const PlyElement* Find(const std::string& element) const;
};

// Reads a whole PLY file. Errors name the file and what was wrong.
Result<PlyData> ReadPly(const std::string& path);
// Parses PLY bytes already in memory (used by the fuzz target); `name` is used in messages.
Result<PlyData> ParsePly(const std::string& bytes, const std::string& name);

// Column-wise binary little-endian writer. Add elements in file order; lists are fixed-length rows.
class PlyWriter {
 public:
  void AddComment(std::string c) { comments_.push_back(std::move(c)); }
  // Starts an element with `count` rows.
  void AddElement(const std::string& name, size_t count);
  // Adds a scalar property to the last element; values.size() must equal its count.
  void AddProperty(const std::string& name, PlyType type, std::vector<double> values);
  // Adds a list property with `row_length` items per row (e.g. 3 for triangle vertex_indices).
  void AddListProperty(const std::string& name, PlyType count_type, PlyType type, int row_length,
                       std::vector<double> values);
  std::string Serialize() const;
  // Writes atomically (temporary file, then rename).
  Status Write(const std::string& path) const;

 private:
  struct Column {
    std::string name;
    PlyType type;
    bool is_list = false;
    PlyType count_type = PlyType::kUInt8;
    int row_length = 1;
    std::vector<double> values;
  };
  struct Element {
    std::string name;
    size_t count;
    std::vector<Column> columns;
  };
  std::vector<std::string> comments_;
  std::vector<Element> elements_;
};

}  // namespace semvox
