#include "render/mesh.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "core/check.h"
#include "render/mesh_file_check.h"

namespace mocap {
namespace {

struct UnitCandidate {
  const char* name;
  double scale_to_m;
};
constexpr UnitCandidate kUnits[] = {{"m", 1.0}, {"cm", 0.01}, {"mm", 0.001}, {"in", 0.0254}};

TextureRgb8 LoadTexture(const aiMaterial* material, const std::filesystem::path& mesh_dir, const std::string& mesh) {
  aiString relative;
  if (material == nullptr || material->GetTexture(aiTextureType_DIFFUSE, 0, &relative) != AI_SUCCESS) return {};
  const std::filesystem::path file = mesh_dir / relative.C_Str();
  const cv::Mat bgr = cv::imread(file.string(), cv::IMREAD_COLOR);
  if (bgr.empty()) throw InputError(mesh, Str("texture '", file.string(), "' is missing or unreadable"));
  TextureRgb8 texture{bgr.cols, bgr.rows, std::vector<uint8_t>(static_cast<size_t>(bgr.cols) * bgr.rows * 3)};
  for (int r = 0; r < bgr.rows; ++r) {
    for (int c = 0; c < bgr.cols; ++c) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(r, c);
      uint8_t* out = &texture.rgb[(static_cast<size_t>(r) * bgr.cols + c) * 3];
      out[0] = p[2], out[1] = p[1], out[2] = p[0];
    }
  }
  return texture;
}

/// Appends one assimp mesh; vertices without colours or UVs get placeholders, dropped by LoadMesh when no
/// part of the file has them.
void AppendMesh(const aiMesh& in, double scale, Mesh& out) {
  const auto base = static_cast<uint32_t>(out.positions_m.size());
  const bool colors = in.HasVertexColors(0), uvs = in.HasTextureCoords(0);
  for (unsigned i = 0; i < in.mNumVertices; ++i) {
    const aiVector3D& p = in.mVertices[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError(out.source, Str("vertex ", i, " has a non-finite coordinate (", p.x, ", ", p.y, ", ", p.z, ")"));
    out.positions_m.emplace_back(static_cast<float>(p.x * scale), static_cast<float>(p.y * scale),
                                 static_cast<float>(p.z * scale));
    if (colors) out.colors.emplace_back(in.mColors[0][i].r, in.mColors[0][i].g, in.mColors[0][i].b, in.mColors[0][i].a);
    else out.colors.emplace_back(0.7f, 0.7f, 0.7f, 1.0f);
    if (uvs) out.uvs.emplace_back(in.mTextureCoords[0][i].x, in.mTextureCoords[0][i].y);
    else out.uvs.emplace_back(0.0f, 0.0f);
  }
  for (unsigned f = 0; f < in.mNumFaces; ++f) {
    const aiFace& face = in.mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines left by triangulation
    for (int k = 0; k < 3; ++k) {
      if (face.mIndices[k] >= in.mNumVertices)
        throw InputError(out.source, Str("face ", f, " refers to vertex ", face.mIndices[k], " of ", in.mNumVertices));
      out.indices.push_back(base + face.mIndices[k]);
    }
  }
}

}  // namespace

Eigen::Vector3f Mesh::min_m() const {
  MOCAP_CHECK(!positions_m.empty(), "empty mesh");
  Eigen::Vector3f m = positions_m.front();
  for (const auto& p : positions_m) m = m.cwiseMin(p);
  return m;
}

Eigen::Vector3f Mesh::max_m() const {
  MOCAP_CHECK(!positions_m.empty(), "empty mesh");
  Eigen::Vector3f m = positions_m.front();
  for (const auto& p : positions_m) m = m.cwiseMax(p);
  return m;
}

double Mesh::extent_m() const { return positions_m.empty() ? 0.0 : static_cast<double>((max_m() - min_m()).norm()); }

void MeshLoadOptions::check() const {
  if (min_extent_m < 0 || max_extent_m < 0 || (max_extent_m > 0 && min_extent_m >= max_extent_m))
    throw InputError("mesh options", Str("plausible extent range ", min_extent_m, "..", max_extent_m, " m is empty"));
}

std::string UnitName(double scale_to_m) {
  for (const auto& unit : kUnits)
    if (std::abs(scale_to_m / unit.scale_to_m - 1.0) < 1e-9) return unit.name;
  return Str(scale_to_m, " m");
}

MeshUnitCheck CheckMeshUnit(const Mesh& mesh, double declared_scale_to_m, const MeshLoadOptions& options) {
  MeshUnitCheck check;
  check.extent_m = mesh.extent_m();
  const bool too_small = options.min_extent_m > 0 && check.extent_m < options.min_extent_m;
  const bool too_big = options.max_extent_m > 0 && check.extent_m > options.max_extent_m;
  if (!too_small && !too_big) return check;
  check.ok = false;
  // The unit whose extent lands in the plausible range, closest (in log scale) to a 20 cm object.
  const double raw_extent = check.extent_m / declared_scale_to_m;
  double best = 1e9;
  for (const auto& unit : kUnits) {
    const double e = raw_extent * unit.scale_to_m;
    if (e < options.min_extent_m || (options.max_extent_m > 0 && e > options.max_extent_m)) continue;
    const double distance = std::abs(std::log(e / 0.2));
    if (distance < best) best = distance, check.likely_scale_to_m = unit.scale_to_m, check.likely_unit = unit.name;
  }
  check.message = Str("mesh extent (bounding-box diagonal) is ", check.extent_m, " m with the declared unit '",
                      UnitName(declared_scale_to_m), "', outside the plausible ", options.min_extent_m, "..",
                      options.max_extent_m, " m");
  if (!check.likely_unit.empty())
    check.message += Str("; the file is probably in '", check.likely_unit, "' (extent ", raw_extent * check.likely_scale_to_m,
                         " m): fix the object's unit");
  return check;
}

Mesh LoadMesh(const std::string& path, double unit_scale_to_m, const MeshLoadOptions& options) {
  options.check();
  if (!(unit_scale_to_m > 0)) throw InputError(path, Str("unit scale ", unit_scale_to_m, " must be positive"));
  if (!std::filesystem::is_regular_file(path)) throw InputError(path, "mesh file not found");
  CheckMeshFile(path);  // assimp crashes on some truncated or inconsistent files; refuse them first
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                     aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (scene == nullptr || scene->mNumMeshes == 0)
    throw InputError(path, Str("cannot read mesh: ", scene ? "it holds no mesh" : importer.GetErrorString()));
  Mesh mesh;
  mesh.source = path;
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  bool any_colors = false, any_uvs = false;
  for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
    const aiMesh& m = *scene->mMeshes[i];
    AppendMesh(m, unit_scale_to_m, mesh);
    any_colors = any_colors || m.HasVertexColors(0);
    any_uvs = any_uvs || m.HasTextureCoords(0);
    if (mesh.texture.empty() && m.HasTextureCoords(0))
      mesh.texture = LoadTexture(scene->mMaterials[m.mMaterialIndex], dir, path);
  }
  if (mesh.indices.empty()) throw InputError(path, "mesh has no triangles");
  if (!any_colors) mesh.colors.clear();
  if (!any_uvs) mesh.uvs.clear();
  const MeshUnitCheck unit = CheckMeshUnit(mesh, unit_scale_to_m, options);
  if (!unit.ok) throw InputError(path, unit.message);
  return mesh;
}

}  // namespace mocap
