// Meshes through assimp. Node transforms are baked in (aiProcess_PreTransformVertices); polygons are
// triangulated; vertex colours, material colours and diffuse / base-colour textures are kept.
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <vector>

#include "core/file_util.h"
#include "core/log.h"
#include "io/image_io.h"
#include "io/load_scene.h"

namespace semvox {
namespace {

uint8_t To8(float v) { return uint8_t(std::clamp(v * 255.0f + 0.5f, 0.0f, 255.0f)); }

Material ConvertMaterial(const aiScene* ai, const aiMaterial* am, const std::string& model_path) {
  Material m;
  aiString name;
  if (am->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) m.name = name.C_Str();
  aiColor4D c;
  if (am->Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS || am->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS)
    m.diffuse = Rgb8{To8(c.r), To8(c.g), To8(c.b)};
  aiString tex;
  bool have = am->GetTexture(aiTextureType_BASE_COLOR, 0, &tex) == AI_SUCCESS ||
              am->GetTexture(aiTextureType_DIFFUSE, 0, &tex) == AI_SUCCESS;
  if (!have) return m;
  m.texture_path = tex.C_Str();
  Result<ImageRgb8> img = Status::Internal("");
  if (const aiTexture* emb = ai->GetEmbeddedTexture(tex.C_Str())) {
    if (emb->mHeight == 0) {
      img = DecodeImageRgb8(std::string(reinterpret_cast<const char*>(emb->pcData), emb->mWidth),
                            model_path + ":" + m.texture_path);
    } else {
      ImageRgb8 raw(int(emb->mWidth), int(emb->mHeight), 3);
      for (unsigned y = 0; y < emb->mHeight; ++y)
        for (unsigned x = 0; x < emb->mWidth; ++x) {
          const aiTexel& t = emb->pcData[y * emb->mWidth + x];
          raw.at(x, y, 0) = t.r, raw.at(x, y, 1) = t.g, raw.at(x, y, 2) = t.b;
        }
      img = std::move(raw);
    }
  } else {
    std::string rel = m.texture_path;
    std::replace(rel.begin(), rel.end(), '\\', '/');
    img = ReadImageRgb8((std::filesystem::path(model_path).parent_path() / rel).string());
  }
  if (img.ok()) {
    m.texture = std::move(img).value();
  } else {
    SEMVOX_WARN(model_path << ": texture '" << m.texture_path << "' not loaded (" << img.status().message()
                           << "); using the material colour");
  }
  return m;
}

// assimp's OBJ/MTL parsers crash on some malformed text (the fuzzer found NUL bytes inside keywords).
// OBJ files are checked line by line before assimp sees them: text only, numbers where numbers belong,
// face indices in range. MTL files named by mtllib are checked for being text.
bool IsTextByte(unsigned char c) { return c >= 0x20 || c == '\t' || c == '\n' || c == '\r'; }

Status CheckObjText(const std::string& bytes, const std::string& name) {
  const std::string kHint = "the OBJ file is corrupt; re-export it";
  long long nv = 0, nvt = 0, nvn = 0;
  size_t pos = 0;
  int line_no = 0;
  while (pos < bytes.size()) {
    size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    std::string line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    for (unsigned char c : line)
      if (!IsTextByte(c))
        return Status::InvalidInput(FileError(name, "line " + std::to_string(line_no) + " holds a binary byte", kHint));
    std::istringstream ls(line);
    std::string key, tok;
    if (!(ls >> key) || key[0] == '#') continue;
    std::vector<std::string> vals;
    while (ls >> tok) vals.push_back(tok);
    auto bad = [&](const std::string& what) {
      return Status::InvalidInput(FileError(name, "line " + std::to_string(line_no) + ": " + what, kHint));
    };
    if (key == "v" || key == "vt" || key == "vn") {
      const size_t lo = key == "vt" ? 1 : 3, hi = key == "v" ? 7 : (key == "vt" ? 3 : 3);
      if (vals.size() < lo || vals.size() > hi) return bad("'" + key + "' with " + std::to_string(vals.size()) + " values");
      for (const auto& v : vals) {
        char* end = nullptr;
        std::strtod(v.c_str(), &end);
        if (*end != '\0') return bad("'" + v + "' is not a number");
      }
      (key == "v" ? nv : key == "vt" ? nvt : nvn)++;
    } else if (key == "f" || key == "l" || key == "p") {
      if (vals.empty()) return bad("'" + key + "' without vertices");
      for (const auto& v : vals) {
        long long idx[3] = {0, 0, 0};
        const long long limit[3] = {nv, nvt, nvn};
        int part = 0;
        size_t i = 0;
        while (true) {
          std::string num;
          while (i < v.size() && v[i] != '/') num += v[i++];
          if (!num.empty()) {
            char* end = nullptr;
            idx[part] = std::strtoll(num.c_str(), &end, 10);
            if (*end != '\0' || idx[part] == 0 || std::llabs(idx[part]) > limit[part])
              return bad("vertex reference '" + v + "' is out of range");
          } else if (part == 0) {
            return bad("vertex reference '" + v + "' has no position index");
          }
          if (i >= v.size()) break;
          ++i;
          if (++part > 2) return bad("vertex reference '" + v + "' has too many parts");
        }
      }
    }
  }
  return Status::Ok();
}

Status CheckObjFile(const std::string& path) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  SEMVOX_RETURN_IF_ERROR(CheckObjText(bytes, path));
  // Material libraries it names.
  std::istringstream is(bytes);
  std::string line;
  while (std::getline(is, line)) {
    if (line.rfind("mtllib", 0) != 0) continue;
    std::istringstream ls(line.substr(6));
    std::string lib;
    while (ls >> lib) {
      const std::string mtl = (std::filesystem::path(path).parent_path() / lib).string();
      std::string mbytes;
      if (!ReadFileBytes(mtl, &mbytes).ok()) continue;  // Missing MTL: assimp warns and uses defaults.
      for (unsigned char c : mbytes)
        if (!IsTextByte(c))
          return Status::InvalidInput(FileError(mtl, "material library holds binary bytes", "re-export the MTL file"));
    }
  }
  return Status::Ok();
}

constexpr unsigned kAssimpFlags = aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType |
                                 aiProcess_ValidateDataStructure | aiProcess_FindInvalidData;

Result<Scene> ConvertAssimpScene(const aiScene* ai, const Assimp::Importer& importer, const std::string& path);

}  // namespace

Result<Scene> LoadAssimpScene(const std::string& path) {
  if (LowerExtension(path) == "obj") SEMVOX_RETURN_IF_ERROR(CheckObjFile(path));
  Assimp::Importer importer;
  // Points and lines are dropped; only triangles matter for surfaces.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  return ConvertAssimpScene(importer.ReadFile(path, kAssimpFlags), importer, path);
}

Result<Scene> LoadAssimpSceneFromMemory(const std::string& bytes, const std::string& extension, const std::string& name) {
  if (extension == "obj") SEMVOX_RETURN_IF_ERROR(CheckObjText(bytes, name));
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  return ConvertAssimpScene(importer.ReadFileFromMemory(bytes.data(), bytes.size(), kAssimpFlags, extension.c_str()),
                            importer, name);
}

namespace {

Result<Scene> ConvertAssimpScene(const aiScene* ai, const Assimp::Importer& importer, const std::string& path) {
  if (!ai || !ai->mRootNode)
    return Status::InvalidInput(FileError(path, std::string("cannot read mesh: ") + importer.GetErrorString(),
                                          "check that the file is complete and of the type its extension says"));
  Scene scene;
  Mesh& mesh = scene.mesh;
  for (unsigned i = 0; i < ai->mNumMaterials; ++i) mesh.materials.push_back(ConvertMaterial(ai, ai->mMaterials[i], path));
  bool any_colors = false, any_uvs = false;
  for (unsigned mi = 0; mi < ai->mNumMeshes; ++mi) {
    any_colors |= ai->mMeshes[mi]->HasVertexColors(0);
    any_uvs |= ai->mMeshes[mi]->HasTextureCoords(0);
  }
  for (unsigned mi = 0; mi < ai->mNumMeshes; ++mi) {
    const aiMesh* am = ai->mMeshes[mi];
    if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const int base = int(mesh.vertices.size());
    const Rgb8 mat_color = am->mMaterialIndex < mesh.materials.size() ? mesh.materials[am->mMaterialIndex].diffuse
                                                                       : Rgb8{200, 200, 200};
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
      const aiVector3D& p = am->mVertices[v];
      mesh.vertices.emplace_back(p.x, p.y, p.z);
      if (any_colors) {
        if (am->HasVertexColors(0)) {
          const aiColor4D& c = am->mColors[0][v];
          mesh.vertex_colors.push_back(Rgb8{To8(c.r), To8(c.g), To8(c.b)});
        } else {
          mesh.vertex_colors.push_back(mat_color);
        }
      }
      if (any_uvs)
        mesh.uvs.push_back(am->HasTextureCoords(0) ? Eigen::Vector2f(am->mTextureCoords[0][v].x, am->mTextureCoords[0][v].y)
                                                   : Eigen::Vector2f(0, 0));
    }
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices != 3) continue;
      mesh.faces.emplace_back(base + int(face.mIndices[0]), base + int(face.mIndices[1]), base + int(face.mIndices[2]));
      mesh.face_material.push_back(int(std::min<unsigned>(am->mMaterialIndex, ai->mNumMaterials ? ai->mNumMaterials - 1 : 0)));
    }
  }
  if (mesh.materials.empty()) {
    mesh.face_material.clear();
  }
  return scene;
}

}  // namespace
}  // namespace semvox
