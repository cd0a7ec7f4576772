// `semvox labels` (docs/labels.md is generated from it) against the spec tables it must reproduce.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "apps/commands.h"

namespace semvox {
namespace {

std::vector<std::vector<std::string>> ReadTsv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // Header.
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, '\t')) cells.push_back(cell);
    if (!cells.empty()) rows.push_back(cells);
  }
  return rows;
}

// Every row of ../shared/spec/nyu40_classes.tsv (id, name, Eigen-13 id and name, NYU-4 id and name) and
// room_types.tsv (id, name) appears verbatim as a table row.
TEST(Labels, MarkdownHasEverySpecRow) {
  const std::string spec = std::string(SEMVOX_SOURCE_DIR) + "/../shared/spec/";
  const auto nyu = ReadTsv(spec + "nyu40_classes.tsv");
  const auto rooms = ReadTsv(spec + "room_types.tsv");
  if (nyu.empty() || rooms.empty()) GTEST_SKIP() << "../shared/spec is absent";
  const std::string md = LabelsMarkdown();
  ASSERT_EQ(nyu.size(), 40u);
  for (const auto& r : nyu) {
    ASSERT_GE(r.size(), 6u);
    const std::string row = "| " + r[0] + " | " + r[1] + " | " + r[2] + " | " + r[3] + " | " + r[4] + " | " + r[5] + " | `#";
    EXPECT_NE(md.find(row), std::string::npos) << row;
  }
  ASSERT_EQ(rooms.size(), 13u);
  for (const auto& r : rooms) {
    const std::string row = "| " + r[0] + " | " + r[1] + " |\n";
    EXPECT_NE(md.find(row), std::string::npos) << row;
  }
  // The super-class tables: 13 Eigen classes and 4 NYU-4 classes.
  const size_t eigen = md.find("## Eigen-13 classes"), nyu4 = md.find("## NYU-4 classes"), room = md.find("## Room types");
  ASSERT_NE(eigen, std::string::npos);
  ASSERT_NE(nyu4, std::string::npos);
  auto rows_between = [&](size_t a, size_t b) {
    size_t n = 0;
    for (size_t p = md.find("\n| ", a); p != std::string::npos && p < b; p = md.find("\n| ", p + 1)) ++n;
    return n - 1;  // Minus the header row.
  };
  EXPECT_EQ(rows_between(eigen, nyu4), 13u);
  EXPECT_EQ(rows_between(nyu4, room), 4u);
}

}  // namespace
}  // namespace semvox
