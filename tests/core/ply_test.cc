#include "core/ply.h"

#include <gtest/gtest.h>

#include "core/mesh_ply.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

TEST(PlyWriter, BinaryRoundTripKeepsEveryProperty) {
  PlyWriter w;
  w.AddElement("vertex", 3);
  w.AddProperty("x", PlyType::kFloat32, {0.5, 1.5, -2.25});
  w.AddProperty("red", PlyType::kUInt8, {0, 128, 255});
  w.AddElement("face", 1);
  w.AddListProperty("vertex_indices", PlyType::kUInt8, PlyType::kInt32, 3, {0, 1, 2});
  w.AddProperty("label", PlyType::kInt32, {-7});
  Result<PlyData> r = ParsePly(w.Serialize(), "mem.ply");
  ASSERT_TRUE(r.ok()) << r.status().message();
  const PlyElement* v = r->Find("vertex");
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(v->count, 3u);
  EXPECT_DOUBLE_EQ(v->Find("x")->values[2], -2.25);
  EXPECT_DOUBLE_EQ(v->Find("red")->values[1], 128);
  const PlyElement* f = r->Find("face");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->Find("vertex_indices")->list_offsets, (std::vector<uint32_t>{0, 3}));
  EXPECT_DOUBLE_EQ(f->Find("label")->values[0], -7);
}

TEST(PlyReader, ParsesAsciiAndBigEndian) {
  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n1 2 3\n4 5 6\n3 0 1 1\n";
  Result<PlyData> r = ParsePly(ascii, "a.ply");
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_DOUBLE_EQ(r->Find("vertex")->Find("z")->values[1], 6);
  std::string big = "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty int x\nend_header\n";
  big += std::string("\x00\x00\x01\x02", 4);
  Result<PlyData> b = ParsePly(big, "b.ply");
  ASSERT_TRUE(b.ok()) << b.status().message();
  EXPECT_DOUBLE_EQ(b->Find("vertex")->Find("x")->values[0], 258);
}

TEST(PlyReader, RejectsBadFilesWithMessagesNamingTheFile) {
  struct Case {
    std::string bytes, expect;
  };
  const std::string head = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nend_header\n";
  const std::vector<Case> cases = {
      {"", "empty"},
      {"PLY\nformat ascii 1.0\nend_header\n", "not a PLY"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "end_header"},
      {"ply\nformat weird 1.0\nend_header\n", "unknown format"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty quux x\nend_header\n1\n", "unknown property type"},
      {head + std::string(8, '\0'), "truncated"},
      {"ply\nformat binary_little_endian 1.0\nelement vertex 999999999999\nproperty float x\nend_header\n" +
           std::string(16, '\0'),
       "holds at most"},
      {"ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list int int vertex_indices\nend_header\n" +
           std::string("\xff\xff\xff\x7f", 4),
       "out of range"},
  };
  for (const Case& c : cases) {
    Result<PlyData> r = ParsePly(c.bytes, "bad.ply");
    ASSERT_FALSE(r.ok()) << c.expect;
    EXPECT_EQ(r.status().code(), StatusCode::kInvalidInput);
    EXPECT_NE(r.status().message().find("bad.ply"), std::string::npos) << r.status().message();
    EXPECT_NE(r.status().message().find(c.expect), std::string::npos) << r.status().message();
  }
}

TEST(MeshPly, WritesFaceAttributesThatReadBack) {
  testing::ScratchDir dir("meshply");
  Mesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.vertex_colors = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
  m.faces = {{0, 1, 2}};
  m.face_attributes["label"] = {33};
  ASSERT_TRUE(WriteMeshPly(dir.File("m.ply"), m).ok());
  Result<PlyData> r = ReadPly(dir.File("m.ply"));
  ASSERT_TRUE(r.ok());
  EXPECT_DOUBLE_EQ(r->Find("face")->Find("label")->values[0], 33);
  EXPECT_DOUBLE_EQ(r->Find("vertex")->Find("green")->values[1], 255);
}

}  // namespace
}  // namespace semvox
