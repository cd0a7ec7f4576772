#include "core/ply.h"

#include <cstring>
#include <fstream>
#include <sstream>
#include <charconv>
#include <bit>

#include "core/file_util.h"

namespace semvox {
namespace {

constexpr uint32_t kMaxListLength = 1u << 16;

bool ParseType(const std::string& s, PlyType* t) {
  static const struct { const char* name; PlyType type; } kTypes[] = {
      {"char", PlyType::kInt8},     {"int8", PlyType::kInt8},      {"uchar", PlyType::kUInt8},
      {"uint8", PlyType::kUInt8},   {"short", PlyType::kInt16},    {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUInt16}, {"uint16", PlyType::kUInt16},  {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},   {"uint", PlyType::kUInt32},    {"uint32", PlyType::kUInt32},
      {"float", PlyType::kFloat32}, {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& e : kTypes)
    if (s == e.name) { *t = e.type; return true; }
  return false;
}

enum class Format { kAscii, kLittle, kBig };

template <typename T>
T LoadRaw(const char* p, bool swap) {
  T v;
  if (!swap) {
    std::memcpy(&v, p, sizeof(T));
  } else {
    char b[sizeof(T)];
    for (size_t i = 0; i < sizeof(T); ++i) b[i] = p[sizeof(T) - 1 - i];
    std::memcpy(&v, b, sizeof(T));
  }
  return v;
}

double LoadBinary(const char* p, PlyType t, bool swap) {
  switch (t) {
    case PlyType::kInt8: return double(LoadRaw<int8_t>(p, false));
    case PlyType::kUInt8: return double(LoadRaw<uint8_t>(p, false));
    case PlyType::kInt16: return double(LoadRaw<int16_t>(p, swap));
    case PlyType::kUInt16: return double(LoadRaw<uint16_t>(p, swap));
    case PlyType::kInt32: return double(LoadRaw<int32_t>(p, swap));
    case PlyType::kUInt32: return double(LoadRaw<uint32_t>(p, swap));
    case PlyType::kFloat32: return double(LoadRaw<float>(p, swap));
    case PlyType::kFloat64: return LoadRaw<double>(p, swap);
  }
  return 0;
}

// Splits on whitespace.
std::vector<std::string> Tokens(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream is(line);
  std::string t;
  while (is >> t) out.push_back(t);
  return out;
}

}  // namespace

int PlyTypeSize(PlyType t) {
  switch (t) {
    case PlyType::kInt8: case PlyType::kUInt8: return 1;
    case PlyType::kInt16: case PlyType::kUInt16: return 2;
    case PlyType::kInt32: case PlyType::kUInt32: case PlyType::kFloat32: return 4;
    case PlyType::kFloat64: return 8;
  }
  return 1;
}

const char* PlyTypeName(PlyType t) {
  switch (t) {
    case PlyType::kInt8: return "char";
    case PlyType::kUInt8: return "uchar";
    case PlyType::kInt16: return "short";
    case PlyType::kUInt16: return "ushort";
    case PlyType::kInt32: return "int";
    case PlyType::kUInt32: return "uint";
    case PlyType::kFloat32: return "float";
    case PlyType::kFloat64: return "double";
  }
  return "?";
}

const PlyProperty* PlyElement::Find(const std::string& property) const {
  for (const auto& p : properties)
    if (p.name == property) return &p;
  return nullptr;
}

const PlyElement* PlyData::Find(const std::string& element) const {
  for (const auto& e : elements)
    if (e.name == element) return &e;
  return nullptr;
}

Result<PlyData> ReadPly(const std::string& path) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  return ParsePly(bytes, path);
}

Result<PlyData> ParsePly(const std::string& bytes, const std::string& name) {
  const std::string kHint = "re-export the file as PLY 1.0 (ascii or binary)";
  if (bytes.empty()) return Status::InvalidInput(FileError(name, "file is empty", "check the path"));
  if (bytes.compare(0, 3, "ply") != 0 || (bytes.size() > 3 && bytes[3] != '\n' && bytes[3] != '\r'))
    return Status::InvalidInput(FileError(name, "not a PLY file (first line is not 'ply')", kHint));

  PlyData data;
  Format format = Format::kAscii;
  bool have_format = false;
  size_t pos = 0;
  bool header_done = false;
  int line_no = 0;
  while (pos < bytes.size()) {
    size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) break;
    std::string line = bytes.substr(pos, eol - pos);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos = eol + 1;
    ++line_no;
    if (line_no > 100000) break;
    if (line_no == 1) continue;  // "ply"
    std::vector<std::string> tok = Tokens(line);
    if (tok.empty()) continue;
    const std::string where = "header line " + std::to_string(line_no);
    if (tok[0] == "end_header") { header_done = true; break; }
    if (tok[0] == "comment" || tok[0] == "obj_info") {
      data.comments.push_back(line.size() > 8 ? line.substr(8) : "");
      continue;
    }
    if (tok[0] == "format") {
      if (tok.size() < 2) return Status::InvalidInput(FileError(name, where + ": incomplete format line", kHint));
      if (tok[1] == "ascii") format = Format::kAscii;
      else if (tok[1] == "binary_little_endian") format = Format::kLittle;
      else if (tok[1] == "binary_big_endian") format = Format::kBig;
      else return Status::InvalidInput(FileError(name, where + ": unknown format '" + tok[1] + "'", kHint));
      have_format = true;
      continue;
    }
    if (tok[0] == "element") {
      if (tok.size() < 3) return Status::InvalidInput(FileError(name, where + ": incomplete element line", kHint));
      PlyElement e;
      e.name = tok[1];
      unsigned long long count = 0;
      auto [p, ec] = std::from_chars(tok[2].data(), tok[2].data() + tok[2].size(), count);
      if (ec != std::errc() || p != tok[2].data() + tok[2].size())
        return Status::InvalidInput(FileError(name, where + ": element count '" + tok[2] + "' is not a number", kHint));
      e.count = size_t(count);
      data.elements.push_back(std::move(e));
      continue;
    }
    if (tok[0] == "property") {
      if (data.elements.empty())
        return Status::InvalidInput(FileError(name, where + ": property before any element", kHint));
      PlyProperty prop;
      if (tok.size() >= 5 && tok[1] == "list") {
        if (!ParseType(tok[2], &prop.count_type) || !ParseType(tok[3], &prop.type))
          return Status::InvalidInput(FileError(name, where + ": unknown list type", kHint));
        if (prop.count_type == PlyType::kFloat32 || prop.count_type == PlyType::kFloat64)
          return Status::InvalidInput(FileError(name, where + ": list count type must be an integer", kHint));
        prop.is_list = true;
        prop.name = tok[4];
      } else if (tok.size() >= 3) {
        if (!ParseType(tok[1], &prop.type))
          return Status::InvalidInput(FileError(name, where + ": unknown property type '" + tok[1] + "'", kHint));
        prop.name = tok[2];
      } else {
        return Status::InvalidInput(FileError(name, where + ": incomplete property line", kHint));
      }
      data.elements.back().properties.push_back(std::move(prop));
      continue;
    }
    return Status::InvalidInput(FileError(name, where + ": unexpected keyword '" + tok[0] + "'", kHint));
  }
  if (!header_done) return Status::InvalidInput(FileError(name, "PLY header has no end_header line", kHint));
  if (!have_format) return Status::InvalidInput(FileError(name, "PLY header has no format line", kHint));

  // Sanity: every element row needs at least one byte per property (binary) or two characters (ascii).
  const size_t body = bytes.size() - pos;
  for (const auto& e : data.elements) {
    size_t min_row = 0;
    for (const auto& p : e.properties)
      min_row += format == Format::kAscii ? 2 : size_t(PlyTypeSize(p.is_list ? p.count_type : p.type));
    if (min_row == 0 && e.count > 0)
      return Status::InvalidInput(FileError(name, "element '" + e.name + "' has rows but no properties", kHint));
    if (min_row > 0 && e.count > body / min_row + 1)
      return Status::InvalidInput(FileError(name, "header declares " + std::to_string(e.count) + " " + e.name +
                                                      " elements but the file holds at most " +
                                                      std::to_string(body / min_row),
                                            "the file is truncated or its header is corrupt"));
  }
  for (auto& e : data.elements)
    for (auto& p : e.properties) {
      if (p.is_list) {
        p.list_offsets.reserve(e.count + 1);
        p.list_offsets.push_back(0);
      } else {
        p.values.reserve(e.count);
      }
    }

  auto truncated = [&](const PlyElement& e, size_t row) {
    return Status::InvalidInput(FileError(name, "truncated PLY: expected " + std::to_string(e.count) + " " + e.name +
                                                    " elements, the data ends at element " + std::to_string(row),
                                          "the file was cut short; re-export or re-download it"));
  };

  if (format == Format::kAscii) {
    const char* p = bytes.data() + pos;
    const char* end = bytes.data() + bytes.size();
    auto next_number = [&](double* v) -> bool {
      while (p < end && (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')) ++p;
      if (p >= end) return false;
      auto [q, ec] = std::from_chars(p, end, *v);
      if (ec != std::errc()) return false;
      p = q;
      return true;
    };
    for (auto& e : data.elements) {
      for (size_t r = 0; r < e.count; ++r) {
        for (auto& prop : e.properties) {
          double v;
          if (!next_number(&v)) {
            if (p >= end) return truncated(e, r);
            return Status::InvalidInput(FileError(name, "bad number in ascii " + e.name + " " + std::to_string(r), kHint));
          }
          if (prop.is_list) {
            if (v < 0 || v > kMaxListLength)
              return Status::InvalidInput(FileError(name, "list length " + std::to_string(v) + " in " + e.name + " " +
                                                              std::to_string(r) + " is out of range", kHint));
            const size_t n = size_t(v);
            for (size_t i = 0; i < n; ++i) {
              double item;
              if (!next_number(&item)) return truncated(e, r);
              prop.list_values.push_back(item);
            }
            prop.list_offsets.push_back(uint32_t(prop.list_values.size()));
          } else {
            prop.values.push_back(v);
          }
        }
      }
    }
  } else {
    const bool swap = (format == Format::kBig) != (std::endian::native == std::endian::big);
    const char* p = bytes.data() + pos;
    const char* end = bytes.data() + bytes.size();
    for (auto& e : data.elements) {
      // Fast path: all scalar properties.
      for (size_t r = 0; r < e.count; ++r) {
        for (auto& prop : e.properties) {
          if (prop.is_list) {
            const int cs = PlyTypeSize(prop.count_type);
            if (end - p < cs) return truncated(e, r);
            double nv = LoadBinary(p, prop.count_type, swap);
            p += cs;
            if (nv < 0 || nv > kMaxListLength)
              return Status::InvalidInput(FileError(name, "list length " + std::to_string(int64_t(nv)) + " in " + e.name +
                                                              " " + std::to_string(r) + " is out of range", kHint));
            const size_t n = size_t(nv);
            const int is = PlyTypeSize(prop.type);
            if (size_t(end - p) < n * is) return truncated(e, r);
            for (size_t i = 0; i < n; ++i, p += is) prop.list_values.push_back(LoadBinary(p, prop.type, swap));
            prop.list_offsets.push_back(uint32_t(prop.list_values.size()));
          } else {
            const int s = PlyTypeSize(prop.type);
            if (end - p < s) return truncated(e, r);
            prop.values.push_back(LoadBinary(p, prop.type, swap));
            p += s;
          }
        }
      }
    }
  }
  return data;
}

void PlyWriter::AddElement(const std::string& name, size_t count) { elements_.push_back({name, count, {}}); }

void PlyWriter::AddProperty(const std::string& name, PlyType type, std::vector<double> values) {
  Column c;
  c.name = name;
  c.type = type;
  c.values = std::move(values);
  elements_.back().columns.push_back(std::move(c));
}

void PlyWriter::AddListProperty(const std::string& name, PlyType count_type, PlyType type, int row_length,
                                std::vector<double> values) {
  Column c;
  c.name = name;
  c.type = type;
  c.is_list = true;
  c.count_type = count_type;
  c.row_length = row_length;
  c.values = std::move(values);
  elements_.back().columns.push_back(std::move(c));
}

namespace {
void StoreBinary(std::string* out, PlyType t, double v) {
  char b[8];
  switch (t) {
    case PlyType::kInt8: { int8_t x = int8_t(v); std::memcpy(b, &x, 1); out->append(b, 1); break; }
    case PlyType::kUInt8: { uint8_t x = uint8_t(v); std::memcpy(b, &x, 1); out->append(b, 1); break; }
    case PlyType::kInt16: { int16_t x = int16_t(v); std::memcpy(b, &x, 2); out->append(b, 2); break; }
    case PlyType::kUInt16: { uint16_t x = uint16_t(v); std::memcpy(b, &x, 2); out->append(b, 2); break; }
    case PlyType::kInt32: { int32_t x = int32_t(v); std::memcpy(b, &x, 4); out->append(b, 4); break; }
    case PlyType::kUInt32: { uint32_t x = uint32_t(v); std::memcpy(b, &x, 4); out->append(b, 4); break; }
    case PlyType::kFloat32: { float x = float(v); std::memcpy(b, &x, 4); out->append(b, 4); break; }
    case PlyType::kFloat64: { std::memcpy(b, &v, 8); out->append(b, 8); break; }
  }
}
}  // namespace

std::string PlyWriter::Serialize() const {
  static_assert(std::endian::native == std::endian::little, "PlyWriter assumes a little-endian host");
  std::string out = "ply\nformat binary_little_endian 1.0\n";
  for (const auto& c : comments_) out += "comment " + c + "\n";
  size_t body = 0;
  for (const auto& e : elements_) {
    out += "element " + e.name + " " + std::to_string(e.count) + "\n";
    for (const auto& c : e.columns) {
      if (c.is_list) {
        out += std::string("property list ") + PlyTypeName(c.count_type) + " " + PlyTypeName(c.type) + " " + c.name + "\n";
        body += e.count * (PlyTypeSize(c.count_type) + size_t(c.row_length) * PlyTypeSize(c.type));
      } else {
        out += std::string("property ") + PlyTypeName(c.type) + " " + c.name + "\n";
        body += e.count * PlyTypeSize(c.type);
      }
    }
  }
  out += "end_header\n";
  out.reserve(out.size() + body);
  for (const auto& e : elements_) {
    for (size_t r = 0; r < e.count; ++r) {
      for (const auto& c : e.columns) {
        if (c.is_list) {
          StoreBinary(&out, c.count_type, c.row_length);
          for (int i = 0; i < c.row_length; ++i) StoreBinary(&out, c.type, c.values[r * c.row_length + i]);
        } else {
          StoreBinary(&out, c.type, c.values[r]);
        }
      }
    }
  }
  return out;
}

Status PlyWriter::Write(const std::string& path) const { return WriteFileAtomic(path, Serialize()); }

}  // namespace semvox
