#include "io/load_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "core/mesh_ply.h"
#include "io/image_io.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

using testing::ScratchDir;
using testing::WriteText;

std::string Base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const uint32_t v = (uint8_t(in[i]) << 16) | (uint8_t(in[i + 1]) << 8) | uint8_t(in[i + 2]);
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], k[v & 63]};
  }
  if (i + 1 == in.size()) {
    const uint32_t v = uint8_t(in[i]) << 16;
    out += {k[v >> 18], k[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const uint32_t v = (uint8_t(in[i]) << 16) | (uint8_t(in[i + 1]) << 8);
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], '='};
  }
  return out;
}

Mesh Triangle() {
  Mesh m;
  m.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 3, 1}};
  m.vertex_colors = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
  m.faces = {{0, 1, 2}};
  m.face_attributes["label"] = {5};
  return m;
}

TEST(LoadScene, BinaryPlyMeshKeepsColoursAndFaceLabels) {
  ScratchDir dir("ply_mesh");
  ASSERT_TRUE(WriteMeshPly(dir.File("m.ply"), Triangle()).ok());
  Result<Scene> s = LoadScene(dir.File("m.ply"));
  ASSERT_TRUE(s.ok()) << s.status().message();
  ASSERT_TRUE(s->is_mesh());
  EXPECT_EQ(s->mesh.faces.size(), 1u);
  EXPECT_EQ(s->mesh.vertex_colors[1], (Rgb8{0, 255, 0}));
  EXPECT_EQ(s->mesh.face_attributes.at("label")[0], 5);
}

TEST(LoadScene, PlyWithoutFacesIsAPointCloud) {
  ScratchDir dir("ply_cloud");
  WriteText(dir.File("c.ply"),
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 0\n"
            "property list uchar int vertex_indices\nend_header\n0 0 0 10 20 30\n1 0 0 40 50 60\n0 1 0 70 80 90\n");
  Result<Scene> s = LoadScene(dir.File("c.ply"));
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_FALSE(s->is_mesh());
  ASSERT_EQ(s->cloud.points.size(), 3u);
  EXPECT_EQ(s->cloud.colors[2], (Rgb8{70, 80, 90}));
}

TEST(LoadScene, ObjWithMtlAndTextureKeepsTheTexture) {
  ScratchDir dir("obj");
  ImageRgb8 tex(4, 4, 3, 0);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) tex.at(x, y, 0) = uint8_t(x * 60), tex.at(x, y, 1) = uint8_t(y * 60), tex.at(x, y, 2) = 7;
  ASSERT_TRUE(WriteImage(dir.File("wood.png"), tex).ok());
  WriteText(dir.File("m.mtl"), "newmtl wood\nKd 0.5 0.25 1.0\nmap_Kd wood.png\nnewmtl plain\nKd 1 0 0\n");
  WriteText(dir.File("m.obj"),
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
            "usemtl wood\nf 1/1 2/2 3/3 4/4\nusemtl plain\nf 1/1 3/3 4/4\n");
  Result<Scene> s = LoadScene(dir.File("m.obj"));
  ASSERT_TRUE(s.ok()) << s.status().message();
  ASSERT_EQ(s->mesh.faces.size(), 3u);  // The quad is triangulated.
  EXPECT_TRUE(s->mesh.has_texture());
  ASSERT_EQ(s->mesh.uvs.size(), s->mesh.vertices.size());
  // Texture lookup: texel (3, 0) in image rows (v = 1 at the top) has red 180, green 0.
  int wood_face = -1, plain_face = -1;
  for (size_t f = 0; f < s->mesh.faces.size(); ++f) {
    const Material& m = s->mesh.materials[s->mesh.face_material[f]];
    (m.texture.empty() ? plain_face : wood_face) = int(f);
  }
  ASSERT_GE(wood_face, 0);
  ASSERT_GE(plain_face, 0);
  EXPECT_EQ(s->mesh.materials[s->mesh.face_material[plain_face]].diffuse, (Rgb8{255, 0, 0}));
  // A point near the vertex with uv (1, 1): texel x = 3, y = 0.
  const Eigen::Vector3i t = s->mesh.faces[wood_face];
  int corner = -1;
  for (int k = 0; k < 3; ++k)
    if ((s->mesh.uvs[t[k]] - Eigen::Vector2f(0.99f, 0.99f)).norm() < 0.05f) corner = k;
  if (corner >= 0) {
    const float u = corner == 1 ? 0.98f : 0.01f, v = corner == 2 ? 0.98f : 0.01f;
    const Rgb8 c = s->mesh.ColorAt(wood_face, u, v);
    EXPECT_EQ(c.r, 180);
    EXPECT_EQ(c.g, 0);
  }
}

TEST(LoadScene, GltfWithVertexColoursIsConvertedFromYUp) {
  ScratchDir dir("gltf");
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 2, 0};  // Y up: the third vertex is 2 m high.
  const float col[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::string bin(reinterpret_cast<const char*>(pos), 36);
  bin.append(reinterpret_cast<const char*>(col), 36);
  const std::string json =
      R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
      R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"COLOR_0":1}}]}],)"
      R"("buffers":[{"byteLength":72,"uri":"data:application/octet-stream;base64,)" + Base64(bin) + R"("}],)"
      R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":36}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,2,0]},)"
      R"({"bufferView":1,"componentType":5126,"count":3,"type":"VEC3"}]})";
  WriteText(dir.File("t.gltf"), json);
  Result<Scene> s = LoadScene(dir.File("t.gltf"));
  ASSERT_TRUE(s.ok()) << s.status().message();
  ASSERT_EQ(s->mesh.faces.size(), 1u);
  ASSERT_EQ(s->mesh.vertex_colors.size(), 3u);
  const Aabb box = s->Bounds();
  EXPECT_NEAR(box.max.z(), 2.0f, 1e-6);  // +Y became +Z.
  EXPECT_NEAR(box.extent().y(), 0.0f, 1e-6);
  bool saw_blue_on_top = false;
  for (size_t i = 0; i < 3; ++i)
    if (s->mesh.vertices[i].z() > 1.9f) saw_blue_on_top = s->mesh.vertex_colors[i] == Rgb8{0, 0, 255};
  EXPECT_TRUE(saw_blue_on_top);
}

TEST(LoadScene, OffAndStlMeshes) {
  ScratchDir dir("off_stl");
  WriteText(dir.File("m.off"), "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
  Result<Scene> off = LoadScene(dir.File("m.off"));
  ASSERT_TRUE(off.ok()) << off.status().message();
  EXPECT_EQ(off->mesh.faces.size(), 2u);
  WriteText(dir.File("m.stl"),
            "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
            "endsolid t\n");
  Result<Scene> stl = LoadScene(dir.File("m.stl"));
  ASSERT_TRUE(stl.ok()) << stl.status().message();
  EXPECT_EQ(stl->mesh.faces.size(), 1u);
}

TEST(LoadScene, PcdAndTextCloudsWithColours) {
  ScratchDir dir("clouds");
  // PCL packs rgb as 0x00RRGGBB reinterpreted as a float; 0x000A141E = (10, 20, 30).
  uint32_t packed = (10u << 16) | (20u << 8) | 30u;
  float as_float;
  std::memcpy(&as_float, &packed, 4);
  char rgb_text[64];
  std::snprintf(rgb_text, sizeof(rgb_text), "%.9g", double(as_float));
  WriteText(dir.File("c.pcd"),
            std::string("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\n"
                        "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n0 0 0 0\n1 2 3 ") +
                std::to_string(packed) + "\n4 5 6 " + std::to_string(packed) + "\n");
  Result<Scene> pcd = LoadScene(dir.File("c.pcd"));
  ASSERT_TRUE(pcd.ok()) << pcd.status().message();
  ASSERT_EQ(pcd->cloud.points.size(), 3u);
  EXPECT_FLOAT_EQ(pcd->cloud.points[2].z(), 6.0f);
  EXPECT_EQ(pcd->cloud.colors[1], (Rgb8{10, 20, 30}));

  WriteText(dir.File("c.txt"), "0 0 0 255 0 0\n1 0 0 0 255 0\n# comment\n0 1 0 0 0 255\n");
  Result<Scene> txt = LoadScene(dir.File("c.txt"));
  ASSERT_TRUE(txt.ok()) << txt.status().message();
  ASSERT_EQ(txt->cloud.points.size(), 3u);
  EXPECT_EQ(txt->cloud.colors[2], (Rgb8{0, 0, 255}));
  WriteText(dir.File("c.xyz"), "0 0 0\n1 0 0\n0 1 0\n");
  Result<Scene> xyz = LoadScene(dir.File("c.xyz"));
  ASSERT_TRUE(xyz.ok());
  EXPECT_FALSE(xyz->cloud.has_colors());
}

TEST(LoadScene, DropsNonFinitePointsAndCountsThem) {
  ScratchDir dir("nan");
  WriteText(dir.File("c.txt"), "0 0 0\nnan nan nan\n1 0 0\n0 1 inf\n0 1 0\n");
  Result<Scene> s = LoadScene(dir.File("c.txt"));
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_EQ(s->cloud.points.size(), 3u);
  EXPECT_EQ(s->dropped_non_finite, 2u);
  WriteText(dir.File("all_nan.txt"), "nan nan nan\nnan 0 0\n");
  Result<Scene> bad = LoadScene(dir.File("all_nan.txt"));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("too little valid geometry"), std::string::npos);
}

TEST(LoadScene, UpAxisAndScale) {
  ScratchDir dir("axes");
  WriteText(dir.File("c.txt"), "0 0 0\n1000 2000 0\n0 0 3000\n");
  LoadOptions opt;
  opt.up = UpAxis::kY;
  opt.scale = 0.001;
  Result<Scene> s = LoadScene(dir.File("c.txt"), opt);
  ASSERT_TRUE(s.ok());
  // (x, y, z) -> (x, -z, y), then scaled.
  EXPECT_TRUE(s->cloud.points[1].isApprox(Eigen::Vector3f(1, 0, 2)));
  EXPECT_TRUE(s->cloud.points[2].isApprox(Eigen::Vector3f(0, -3, 0)));
  opt.scale = -1;
  EXPECT_FALSE(LoadScene(dir.File("c.txt"), opt).ok());
}

// Every axis can be the file's up: the point on it lands on +Z, and the turn is a rotation (a right-handed frame
// stays right-handed). A camera's frame (-y: x right, y down, z forward) keeps x and looks along +Y.
TEST(LoadScene, AnyAxisCanBeUp) {
  ScratchDir dir("any_axis");
  WriteText(dir.File("c.txt"), "1 0 0\n0 1 0\n0 0 1\n-1 0 0\n0 -1 0\n0 0 -1\n");
  const std::vector<std::pair<std::string, int>> axes = {{"z", 2}, {"+y", 1}, {"-y", 4}, {"x", 0}, {"-x", 3}, {"-z", 5}};
  for (const auto& [name, row] : axes) {
    LoadOptions opt;
    ASSERT_TRUE(ParseUpAxis(name, &opt.up)) << name;
    Result<Scene> s = LoadScene(dir.File("c.txt"), opt);
    ASSERT_TRUE(s.ok()) << name;
    const auto& p = s->cloud.points;
    EXPECT_TRUE(p[size_t(row)].isApprox(Eigen::Vector3f(0, 0, 1))) << name << ": " << p[size_t(row)].transpose();
    EXPECT_TRUE(p[0].cross(p[1]).isApprox(p[2])) << name << ": not a rotation";
  }
  LoadOptions camera;
  ASSERT_TRUE(ParseUpAxis("-y", &camera.up));
  Result<Scene> s = LoadScene(dir.File("c.txt"), camera);
  ASSERT_TRUE(s.ok());
  EXPECT_TRUE(s->cloud.points[0].isApprox(Eigen::Vector3f(1, 0, 0)));  // x stays right
  EXPECT_TRUE(s->cloud.points[2].isApprox(Eigen::Vector3f(0, 1, 0)));  // forward becomes +Y
  UpAxis up;
  EXPECT_FALSE(ParseUpAxis("up", &up));
  EXPECT_FALSE(ParseUpAxis("--y", &up));
}

TEST(LoadScene, BadInputsGiveOneClearError) {
  ScratchDir dir("bad");
  WriteText(dir.File("empty.ply"), "");
  WriteText(dir.File("magic.ply"), "not a ply at all\n");
  ASSERT_TRUE(WriteMeshPly(dir.File("full.ply"), Triangle()).ok());
  const std::string full = testing::ReadText(dir.File("full.ply"));
  WriteText(dir.File("trunc.ply"), full.substr(0, full.size() - 10));
  WriteText(dir.File("nofaces.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  WriteText(dir.File("x.foo"), "hello");
  WriteText(dir.File("bad.txt"), "1 2 3\n4 five 6\n");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {dir.File("missing.ply"), "no such file"}, {dir.File("empty.ply"), "empty"},
      {dir.File("magic.ply"), "not a PLY"},      {dir.File("trunc.ply"), "truncated"},
      {dir.File("nofaces.obj"), "no faces"},     {dir.File("x.foo"), "unsupported file extension"},
      {dir.File("bad.txt"), "line 2"},           {dir.path().string(), "directory"},
  };
  for (const auto& [path, expect] : cases) {
    Result<Scene> s = LoadScene(path);
    ASSERT_FALSE(s.ok()) << path;
    EXPECT_EQ(s.status().code(), StatusCode::kInvalidInput) << path;
    EXPECT_NE(s.status().message().find(expect), std::string::npos) << s.status().message();
    EXPECT_EQ(s.status().message().find('\n'), std::string::npos) << "one line: " << s.status().message();
  }
}

}  // namespace
}  // namespace semvox
