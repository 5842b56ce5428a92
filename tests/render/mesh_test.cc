#include "render/mesh.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include "core/check.h"
#include "render/mesh_file_check.h"
#include "render/primitives.h"

namespace mocap {
namespace {

const std::string kModels = std::string(MOCAP_SHARED_DIR) + "/realdata/bop_lmo_scene2/models";

std::string WriteTempObj(const std::string& name, double scale) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream out(path);
  // A tetrahedron with 10-unit edges along the axes.
  out << "v 0 0 0\nv " << 10 * scale << " 0 0\nv 0 " << 10 * scale << " 0\nv 0 0 " << 10 * scale << "\n"
      << "f 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n";
  return path.string();
}

TEST(Mesh, LoadsBopPlyInMillimetresWithColours) {
  const Mesh mesh = LoadMesh(kModels + "/obj_000001.ply", 0.001);
  EXPECT_EQ(mesh.positions_m.size(), 5841u);  // the PLY header's vertex count
  EXPECT_EQ(mesh.triangle_count(), 11678u);
  ASSERT_EQ(mesh.colors.size(), mesh.positions_m.size());
  EXPECT_NEAR(mesh.colors[0].x(), 148.0 / 255.0, 1e-3);  // first vertex: 148 57 57
  EXPECT_NEAR(mesh.positions_m[0].x(), -0.0230565, 1e-6);
  // models_info.json: obj 1 size 75.9 x 77.6 x 91.8 mm; bounding-box diagonal 142.2 mm.
  EXPECT_NEAR(mesh.extent_m(), 0.1422, 0.0005);
  EXPECT_TRUE(mesh.uvs.empty());
}

TEST(Mesh, MillimetreMeshDeclaredAsMetresIsAClearError) {
  try {
    LoadMesh(kModels + "/obj_000001.ply", 1.0);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("obj_000001.ply"), std::string::npos) << what;
    EXPECT_NE(what.find("142."), std::string::npos) << "names the extent: " << what;
    EXPECT_NE(what.find("probably in 'mm'"), std::string::npos) << what;
  }
  const MeshUnitCheck check = CheckMeshUnit(LoadMesh(kModels + "/obj_000001.ply", 1.0, {0, 0}), 1.0);
  EXPECT_FALSE(check.ok);
  EXPECT_EQ(check.likely_unit, "mm");
  EXPECT_DOUBLE_EQ(check.likely_scale_to_m, 0.001);
}

TEST(Mesh, MetreMeshDeclaredAsMillimetresIsTooSmall) {
  const std::string path = WriteTempObj("mocap_mesh_test_m.obj", 0.01);  // 10 cm edges, in metres
  EXPECT_NEAR(LoadMesh(path, 1.0).extent_m(), 0.1 * std::sqrt(3.0), 1e-6);
  try {
    LoadMesh(path, 0.001);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("probably in 'm'"), std::string::npos) << e.what();
  }
}

TEST(Mesh, GeneratedObjInCentimetres) {
  const std::string path = WriteTempObj("mocap_mesh_test_cm.obj", 1.0);  // 10 cm edges, in cm
  const Mesh mesh = LoadMesh(path, 0.01);
  EXPECT_EQ(mesh.triangle_count(), 4u);
  EXPECT_NEAR(mesh.max_m().x(), 0.1, 1e-7);
  EXPECT_TRUE(mesh.colors.empty());
}

TEST(Mesh, MissingFileNamesIt) {
  try {
    LoadMesh("/nonexistent/dir/obj_000042.ply", 0.001);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "/nonexistent/dir/obj_000042.ply");
    EXPECT_NE(std::string(e.what()).find("not found"), std::string::npos);
  }
}

TEST(Mesh, UnreadableFilesAreErrors) {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string not_ply = (dir / "mocap_mesh_test_text.ply").string(), empty = (dir / "mocap_mesh_test_empty.obj").string();
  std::ofstream(not_ply) << "this is not a mesh\n";
  std::ofstream(empty) << "";
  // The PLY check (mesh_file_check.h) refuses the text before assimp sees it; assimp refuses the empty OBJ.
  for (const auto& [path, expected] : {std::pair{not_ply, "not a PLY file"}, std::pair{empty, "cannot read mesh"}}) {
    try {
      LoadMesh(path, 0.001);
      ADD_FAILURE() << "expected InputError for " << path;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where(), path);
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

// ---- Truncated or inconsistent mesh files (mesh_file_check.h): one clear InputError, never a crash. Before
// the check, assimp aborted (ai_assert in TriangulateProcess.cpp) on the cut text PLY, crashed (SIGSEGV) on
// the cut binary PLYs and on a face index far out of range, and loaded NaN vertices and a text PLY with a
// missing row as if they were whole.

namespace fs = std::filesystem;

/// A fresh folder for the current test's files, removed with the object.
class TestDir {
 public:
  TestDir() {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / Str("mocap_mesh_check_", ::getpid(), "_", test->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TestDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

std::string ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

std::string WriteBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

template <typename T>
void Append(std::string& bytes, T value) {
  bytes.append(reinterpret_cast<const char*>(&value), sizeof(T));  // little-endian hosts
}

/// A binary little-endian PLY of the given vertices (mm) and triangles.
std::string BinaryPly(const std::vector<Eigen::Vector3f>& vertices, const std::vector<Eigen::Vector3i>& faces) {
  std::string ply = Str("ply\nformat binary_little_endian 1.0\nelement vertex ", vertices.size(),
                        "\nproperty float x\nproperty float y\nproperty float z\nelement face ", faces.size(),
                        "\nproperty list uchar int vertex_indices\nend_header\n");
  for (const auto& v : vertices) Append(ply, v.x()), Append(ply, v.y()), Append(ply, v.z());
  for (const auto& f : faces) Append(ply, uint8_t{3}), Append(ply, f.x()), Append(ply, f.y()), Append(ply, f.z());
  return ply;
}

const std::vector<Eigen::Vector3f> kTetraMm = {{0, 0, 0}, {100, 0, 0}, {0, 100, 0}, {0, 0, 100}};
const std::vector<Eigen::Vector3i> kTetraFaces = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
const std::string kTetraAsciiHeader =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kTetraAsciiVertices = "0 0 0\n100 0 0\n0 100 0\n0 0 100\n";
const std::string kTetraAsciiFaces = "3 0 1 2\n3 0 1 3\n3 0 2 3\n3 1 2 3\n";

/// LoadMesh must throw an InputError naming `path` whose message holds every one of `parts`.
void ExpectMeshError(const std::string& path, std::initializer_list<std::string> parts) {
  try {
    LoadMesh(path, 0.001);
    ADD_FAILURE() << "expected InputError for " << path;
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), path);
    for (const std::string& part : parts) EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(MeshFileCheck, TextPlyCutInsideItsVertexList) {
  const std::string bytes = ReadBytes(kModels + "/obj_000008.ply").substr(0, 400000);  // header: 17 lines
  const TestDir dir;
  ExpectMeshError(WriteBytes(dir / "cut.ply", bytes),
                  {"file ends inside the vertex list", "of 12655 declared", "line "});
}

/// Offset of the first byte after the header of a PLY.
size_t BodyOffset(const std::string& ply) { return ply.find("end_header\n") + std::strlen("end_header\n"); }

TEST(MeshFileCheck, BinaryPlyCutInsideItsFaceList) {
  // models_eval/obj_000008.ply: 10215 vertices of 3 floats, 20426 faces of 1 + 3 * 4 bytes.
  const std::string ply = ReadBytes(std::string(MOCAP_SHARED_DIR) + "/realdata/bop_lmo_scene2/models_eval/obj_000008.ply");
  const size_t cut = BodyOffset(ply) + 10215 * 12 + 100 * 13 + 5;
  const TestDir dir;
  ExpectMeshError(WriteBytes(dir / "cut.ply", ply.substr(0, cut)),
                  {Str("byte ", cut, ": file ends inside the face list (face 100 of 20426 declared)")});
}

TEST(MeshFileCheck, BinaryPlyCutInsideItsVertexList) {
  const std::string ply = ReadBytes(std::string(MOCAP_SOURCE_DIR) + "/meshes/funnel.ply");
  const size_t cut = BodyOffset(ply) + 15 * 15 + 7;  // vertices: 3 floats + 3 colour bytes
  const TestDir dir;
  ExpectMeshError(WriteBytes(dir / "cut.ply", ply.substr(0, cut)),
                  {Str("byte ", cut, ": file ends inside the vertex list (vertex 15 of 864 declared)")});
}

TEST(MeshFileCheck, FaceIndexOutOfRange) {
  const TestDir dir;
  for (const int bad : {4, 100000, -1}) {
    std::vector<Eigen::Vector3i> faces = kTetraFaces;
    faces[3].z() = bad;
    const std::string ply = BinaryPly(kTetraMm, faces);
    const size_t at = BodyOffset(ply) + 4 * 12 + 3 * 13 + 9;
    ExpectMeshError(WriteBytes(dir / "index.ply", ply),
                    {Str("byte ", at, ": face 3 refers to vertex ", bad, ", but the file declares 4 vertices")});
  }
  ExpectMeshError(WriteBytes(dir / "index.ply", kTetraAsciiHeader + kTetraAsciiVertices + "3 0 1 2\n3 0 1 4\n"),
                  {"line 15: face 1 refers to vertex 4"});
}

TEST(MeshFileCheck, TextPlyWithAMissingRow) {
  const TestDir dir;
  // The vertex list lacks a row: the first face row is read as the last vertex and has a value too many.
  ExpectMeshError(WriteBytes(dir / "vertex.ply", kTetraAsciiHeader + "0 0 0\n100 0 0\n0 100 0\n" + kTetraAsciiFaces),
                  {"line 13: vertex 3 has 4 values, its properties take 3"});
  ExpectMeshError(WriteBytes(dir / "face.ply", kTetraAsciiHeader + kTetraAsciiVertices + "3 0 1 2\n3 0 1 3\n"),
                  {"line 16: file ends inside the face list (face 2 of 4 declared)"});
}

TEST(MeshFileCheck, NonFiniteVertexCoordinates) {
  const TestDir dir;
  std::vector<Eigen::Vector3f> vertices = kTetraMm;
  vertices[1].y() = std::nanf("");
  const std::string ply = BinaryPly(vertices, kTetraFaces);
  ExpectMeshError(WriteBytes(dir / "nan.ply", ply),
                  {Str("byte ", BodyOffset(ply) + 16, ": vertex 1 has a non-finite coordinate y")});
  ExpectMeshError(WriteBytes(dir / "inf.ply", kTetraAsciiHeader + "0 0 0\n100 0 0\n0 100 inf\n0 0 100\n" + kTetraAsciiFaces),
                  {"line 12: vertex 2 has a non-finite coordinate z"});
  ExpectMeshError(WriteBytes(dir / "nan.obj", "v 0 0 0\nv 0.1 nan 0\nv 0 0.1 0\nf 1 2 3\n"),
                  {"line 2: vertex coordinate 'nan' is not finite"});
  ExpectMeshError(WriteBytes(dir / "text.obj", "v 0 0 0\nv 0.1 abc 0\nv 0 0.1 0\nf 1 2 3\n"),
                  {"line 2: vertex coordinate 'abc' is not a number"});
}

TEST(MeshFileCheck, ObjFaceIndexOutOfRange) {
  const TestDir dir;
  const std::string tetra = "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\n";
  ExpectMeshError(WriteBytes(dir / "positive.obj", tetra + "f 1 2 3\nf 1 2 5\n"),
                  {"line 6: vertex index 5 is out of range: 4 vertices declared so far"});
  ExpectMeshError(WriteBytes(dir / "relative.obj", tetra + "f -1 -2 -3\nf -1 -2 -5\n"),
                  {"line 6: vertex index -5 is out of range"});
  ExpectMeshError(WriteBytes(dir / "before.obj", "v 0 0 0\nv 0.1 0 0\nf 1 2 3\nv 0 0.1 0\n"), {"line 3: vertex index 3"});
  ExpectMeshError(WriteBytes(dir / "uv.obj", tetra + "vt 0 0\nf 1/1 2/2 3/1\n"), {"line 6: texture coordinate index 2"});
  const std::string ok = WriteBytes(dir / "ok.obj", tetra + "vt 0 0\nvn 0 0 1\nf 1/1/1 2//1 -1/-1/-1\n");
  EXPECT_EQ(LoadMesh(ok, 1.0).triangle_count(), 1u);
}

TEST(MeshFileCheck, BinaryStlOfTheWrongSize) {
  std::string stl(80, '\0');
  Append(stl, uint32_t{40});  // declares 40 triangles, holds 4
  for (int t = 0; t < 4; ++t) {
    for (const float v : {0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 0.1f, 0.f, 0.f, 0.f, 0.1f, 0.f}) Append(stl, v);
    Append(stl, uint16_t{0});
  }
  const TestDir dir;
  ExpectMeshError(WriteBytes(dir / "short.stl", stl),
                  {"byte 80: binary STL declares 40 triangles", "= 2084 bytes", "has 284 bytes"});
  ExpectMeshError(WriteBytes(dir / "header.stl", stl.substr(0, 50)), {"byte 50: file ends inside the 84-byte header"});
  stl[80] = 4;  // now consistent
  EXPECT_EQ(LoadMesh(WriteBytes(dir / "ok.stl", stl), 1.0).triangle_count(), 4u);
}

TEST(MeshFileCheck, IntactMeshesStillLoad) {
  for (const auto& entry : fs::directory_iterator(kModels)) {
    if (entry.path().extension() != ".ply") continue;
    EXPECT_NO_THROW(CheckMeshFile(entry.path().string())) << entry.path();
    EXPECT_GT(LoadMesh(entry.path().string(), 0.001).triangle_count(), 1000u) << entry.path();
  }
  const std::string eval = std::string(MOCAP_SHARED_DIR) + "/realdata/bop_lmo_scene2/models_eval";
  for (const auto& entry : fs::directory_iterator(eval)) {
    if (entry.path().extension() != ".ply") continue;
    EXPECT_NO_THROW(CheckMeshFile(entry.path().string())) << entry.path();
  }
  for (const auto& entry : fs::directory_iterator(std::string(MOCAP_SOURCE_DIR) + "/meshes")) {
    if (entry.path().extension() != ".ply") continue;
    EXPECT_GT(LoadMesh(entry.path().string(), 1.0).triangle_count(), 10u) << entry.path();
  }
  // A big-endian PLY of the same tetrahedron, and the text one whole.
  std::string big =
      "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 4\nproperty list uchar ushort vertex_indices\nend_header\n";
  auto append_big = [&big](auto value) {
    char raw[sizeof(value)];
    std::memcpy(raw, &value, sizeof(value));
    for (size_t i = sizeof(value); i-- > 0;) big.push_back(raw[i]);
  };
  for (const auto& v : kTetraMm) append_big(double{v.x()}), append_big(double{v.y()}), append_big(double{v.z()});
  for (const auto& f : kTetraFaces) {
    big.push_back(3);
    for (int k = 0; k < 3; ++k) append_big(static_cast<uint16_t>(f[k]));
  }
  const TestDir dir;
  EXPECT_EQ(LoadMesh(WriteBytes(dir / "big.ply", big), 0.001).triangle_count(), 4u);
  const std::string text = WriteBytes(dir / "text.ply", kTetraAsciiHeader + kTetraAsciiVertices + kTetraAsciiFaces);
  EXPECT_EQ(LoadMesh(text, 0.001).triangle_count(), 4u);
}

TEST(MeshFileCheck, HeaderProblems) {
  const TestDir dir;
  ExpectMeshError(WriteBytes(dir / "type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n1\n"),
                  {"line 4: unknown PLY type 'float128'"});
  ExpectMeshError(WriteBytes(dir / "end.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"),
                  {"line 5: file ends inside the PLY header (no end_header line)"});
  ExpectMeshError(WriteBytes(dir / "count.ply",
                             "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n"),
                  {"line 3: element 'vertex' declares 4000000000 rows"});
  ExpectMeshError(WriteBytes(dir / "corners.ply", kTetraAsciiHeader + kTetraAsciiVertices + "3 0 1 2\n200 0 1 3\n"),
                  {"line 15: face 1 has 200 corners; a face has 3..64"});
}

TEST(Mesh, UnitNames) {
  EXPECT_EQ(UnitName(0.001), "mm");
  EXPECT_EQ(UnitName(1.0), "m");
  EXPECT_EQ(UnitName(0.0254), "in");
}

TEST(Primitives, BoxAndSphereSizes) {
  const Mesh box = MakeBoxMesh({0.1, 0.2, 0.3});
  EXPECT_EQ(box.triangle_count(), 12u);
  EXPECT_NEAR(box.extent_m(), std::sqrt(0.01 + 0.04 + 0.09), 1e-6);
  const Mesh sphere = MakeSphereMesh(0.05, 20000);
  EXPECT_NEAR(static_cast<double>(sphere.triangle_count()), 20000, 1000);
}

}  // namespace
}  // namespace mocap
