// "x y z [r g b]" text clouds (S3DIS .txt, .xyz) and .pts ("x y z intensity r g b", optional count line).
#include <charconv>
#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/file_util.h"
#include "io/load_scene.h"

namespace semvox {

Result<Scene> LoadTextCloud(const std::string& path) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  return ParseTextCloud(bytes, path);
}

Result<Scene> ParseTextCloud(const std::string& bytes, const std::string& name) {
  const bool pts = LowerExtension(name) == "pts";
  Scene scene;
  PointCloud& cloud = scene.cloud;
  const char* p = bytes.data();
  const char* end = p + bytes.size();
  size_t line_no = 0;
  int columns = -1;
  double v[16];
  while (p < end) {
    const char* eol = static_cast<const char*>(memchr(p, '\n', size_t(end - p)));
    if (!eol) eol = end;
    ++line_no;
    int n = 0;
    const char* q = p;
    bool bad = false;
    while (q < eol) {
      while (q < eol && (*q == ' ' || *q == '\t' || *q == ',' || *q == ';' || *q == '\r')) ++q;
      if (q >= eol || *q == '#') break;
      if (n == 16) { bad = true; break; }
      auto [r, ec] = std::from_chars(q, eol, v[n]);
      if (ec != std::errc()) {
        // "nan" and "inf" are accepted by from_chars; anything else is an error.
        bad = true;
        break;
      }
      q = r;
      ++n;
    }
    if (bad)
      return Status::InvalidInput(FileError(name, "line " + std::to_string(line_no) + " is not a row of numbers",
                                            "expected 'x y z' or 'x y z r g b' per line"));
    p = eol + 1;
    if (n == 0) continue;
    if (n == 1 && cloud.points.empty()) continue;  // Point count header (.pts).
    if (n < 3)
      return Status::InvalidInput(FileError(name, "line " + std::to_string(line_no) + " has " + std::to_string(n) +
                                                      " values, expected at least 3 (x y z)",
                                            "expected 'x y z' or 'x y z r g b' per line"));
    if (columns < 0) columns = n;
    cloud.points.emplace_back(float(v[0]), float(v[1]), float(v[2]));
    const int c0 = pts && n >= 7 ? 4 : 3;  // .pts: x y z intensity r g b.
    if (columns >= c0 + 3 && n >= c0 + 3) {
      const bool unit = v[c0] <= 1.0 && v[c0 + 1] <= 1.0 && v[c0 + 2] <= 1.0 && (v[c0] != std::floor(v[c0]) ||
                                                                                 v[c0 + 1] != std::floor(v[c0 + 1]));
      auto to8 = [&](double x) { return uint8_t(std::clamp(unit ? x * 255.0 + 0.5 : x, 0.0, 255.0)); };
      if (cloud.colors.size() + 1 < cloud.points.size()) cloud.colors.resize(cloud.points.size() - 1, Rgb8{128, 128, 128});
      cloud.colors.push_back(Rgb8{to8(v[c0]), to8(v[c0 + 1]), to8(v[c0 + 2])});
    }
  }
  if (!cloud.colors.empty()) cloud.colors.resize(cloud.points.size(), Rgb8{128, 128, 128});
  if (cloud.points.empty())
    return Status::InvalidInput(FileError(name, "no points found", "expected 'x y z' or 'x y z r g b' per line"));
  return scene;
}

}  // namespace semvox
