// Mesh loading: OBJ through tinyobjloader, our own PLY reader. The binary PLY
// fixtures are written here, from the same description as the ASCII one, so
// the three encodings are known to hold the same mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "host/error.h"
#include "host/scene/load_scene.h"
#include "host/scene/mesh.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

std::string fixture(const std::string& name) { return test::source_dir() + "/tests/data/mesh/" + name; }

std::string write_file(const std::string& name, const std::string& bytes) {
  const std::string path = test::temp_dir() + "/" + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

using test::error_of;

float area(const MeshTriangle& t) { return 0.5f * glm::length(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0])); }
glm::vec3 normal_of(const MeshTriangle& t) { return glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]); }

TEST(MeshObj, TriangulatesQuadPentagonAndConcavePolygon) {
  const Mesh m = load_mesh(fixture("polygons.obj"));
  EXPECT_EQ(m.source_faces, 3u);
  ASSERT_EQ(m.triangles.size(), 2u + 3u + 4u);
  EXPECT_EQ(m.dropped_degenerate, 0u);
  EXPECT_TRUE(m.warnings.empty());
  // Convex faces become a fan from their first corner.
  EXPECT_EQ(m.triangles[0].p[0], glm::vec3(0, 0, 0));
  EXPECT_EQ(m.triangles[0].p[1], glm::vec3(1, 0, 0));
  EXPECT_EQ(m.triangles[0].p[2], glm::vec3(1, 1, 0));
  EXPECT_EQ(m.triangles[1].p[0], glm::vec3(0, 0, 0));
  EXPECT_EQ(m.triangles[1].p[1], glm::vec3(1, 1, 0));
  EXPECT_EQ(m.triangles[1].p[2], glm::vec3(0, 1, 0));
  const glm::vec3 pent[5] = {{3, 0, 0}, {4, 0, 0}, {4.5f, 1, 0}, {3.5f, 2, 0}, {2.5f, 1, 0}};
  for (int k = 0; k < 3; ++k) {
    const MeshTriangle& t = m.triangles[2 + k];
    EXPECT_EQ(t.p[0], pent[0]);
    EXPECT_EQ(t.p[1], pent[k + 1]);
    EXPECT_EQ(t.p[2], pent[k + 2]);
  }
  // The L: all pieces keep the face's winding, stay inside it and cover it.
  float total = 0.0f;
  for (size_t i = 5; i < m.triangles.size(); ++i) {
    const MeshTriangle& t = m.triangles[i];
    EXPECT_GT(normal_of(t).z, 0.0f) << "triangle " << i;
    const glm::vec3 c = (t.p[0] + t.p[1] + t.p[2]) / 3.0f;
    EXPECT_TRUE(c.x < 11.0f || c.y < 1.0f) << "triangle " << i << " covers the notch";
    total += area(t);
  }
  EXPECT_NEAR(total, 3.0f, 1e-5f);
  for (const auto& t : m.triangles) {
    EXPECT_FALSE(t.has_normals);
    EXPECT_FALSE(t.has_uvs);
    EXPECT_EQ(t.material, -1);
  }
}

TEST(MeshObj, NegativeIndicesAreRelativeToVerticesSoFar) {
  const Mesh m = load_mesh(fixture("negative.obj"));
  ASSERT_EQ(m.triangles.size(), 3u);
  EXPECT_EQ(m.triangles[0].p[1], glm::vec3(1, 0, 0));
  EXPECT_EQ(m.triangles[1].p[0], glm::vec3(5, 0, 0));
  EXPECT_EQ(m.triangles[1].p[2], glm::vec3(5, 1, 0));
  EXPECT_EQ(m.triangles[2].p[0], glm::vec3(0, 0, 0));
  EXPECT_EQ(m.triangles[2].p[1], glm::vec3(6, 0, 0));
  EXPECT_EQ(m.triangles[2].p[2], glm::vec3(5, 1, 0));
}

TEST(MeshObj, TextureCoordinatesAndNormalsPerFace) {
  const Mesh m = load_mesh(fixture("attributes.obj"));
  ASSERT_EQ(m.triangles.size(), 6u);
  const bool expect_n[6] = {true, true, false, false, false, false};
  const bool expect_uv[6] = {true, false, true, false, true, true};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(m.triangles[i].has_normals, expect_n[i]) << "face " << i + 1;
    EXPECT_EQ(m.triangles[i].has_uvs, expect_uv[i]) << "face " << i + 1;
  }
  for (const auto& n : m.triangles[0].n) EXPECT_EQ(n, glm::vec3(0, 0, 1));  // normalised from (0 0 2)
  EXPECT_EQ(m.triangles[0].uv[1], glm::vec2(1, 0));
  EXPECT_EQ(m.triangles[0].uv[2], glm::vec2(0, 1));
}

TEST(MeshObj, MaterialsFromMtl) {
  const Mesh m = load_mesh(fixture("materials.obj"));
  EXPECT_TRUE(m.warnings.empty()) << m.warnings.front();
  ASSERT_EQ(m.materials.size(), 2u);
  const MeshMaterial& red = m.materials[0];
  EXPECT_EQ(red.name, "red");
  EXPECT_EQ(red.kd, glm::vec3(0.7f, 0.1f, 0.05f));
  EXPECT_EQ(red.ks, glm::vec3(0.2f, 0.3f, 0.4f));
  EXPECT_EQ(red.ke, glm::vec3(0.0f));
  EXPECT_FLOAT_EQ(red.ns, 50.0f);
  // Relative texture paths are joined to the OBJ's folder.
  EXPECT_EQ(red.diffuse_texture, test::source_dir() + "/tests/data/mesh/textures/brick.png");
  const MeshMaterial& lamp = m.materials[1];
  EXPECT_EQ(lamp.ke, glm::vec3(17, 12, 4));
  EXPECT_FLOAT_EQ(lamp.ns, 1.0f);
  EXPECT_TRUE(lamp.diffuse_texture.empty());

  ASSERT_EQ(m.triangles.size(), 4u);
  EXPECT_EQ(m.triangles[0].material, -1);  // before any usemtl
  EXPECT_EQ(m.triangles[1].material, 0);
  EXPECT_EQ(m.triangles[2].material, 1);
  EXPECT_EQ(m.triangles[3].material, 1);
}

TEST(MeshObj, MissingMtlIsAWarningNamingTheFile) {
  const Mesh m = load_mesh(fixture("missing_mtl.obj"));
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0].material, -1);
  ASSERT_FALSE(m.warnings.empty());
  bool named = false;
  for (const auto& w : m.warnings) named = named || w.find("does_not_exist.mtl") != std::string::npos;
  EXPECT_TRUE(named) << m.warnings.front();
}

TEST(MeshObj, DegenerateTrianglesAreDroppedAndCounted) {
  const Mesh m = load_mesh(fixture("degenerate.obj"));
  EXPECT_EQ(m.source_faces, 6u);
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.dropped_degenerate, 5u);
  EXPECT_EQ(m.triangles[0].p[2], glm::vec3(0, 1, 0));
}

// tinyobjloader reads "nan" as 0 and an index of 10^20 through atoi (in
// practice the last vertex); the text is checked first, so these are errors
// naming the file and line (issue 14).
TEST(MeshObj, NonFiniteValuesAndHugeIndicesAreErrors) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const struct {
    std::string text;
    std::vector<std::string> parts;
  } cases[] = {
      {tri + "v nan 1 0\nf 1 2 4\n", {"line 4", "finite vertex coordinate", "'nan'"}},
      {tri + "v 0 inf 0\nf 1 2 4\n", {"line 4", "'inf'"}},
      {tri + "v 0 1e40 0\nf 1 2 4\n", {"line 4", "'1e40'"}},
      {tri + "v 0 abc 0\nf 1 2 4\n", {"line 4", "'abc'"}},
      {tri + "vn 0 0 nan\nf 1//1 2//1 3//1\n", {"line 4", "finite normal component"}},
      {tri + "vt 0.5 -inf\nf 1/1 2/1 3/1\n", {"line 4", "finite texture coordinate"}},
      {tri + "f 1 2 100000000000000000000\n", {"line 4", "face indices", "'100000000000000000000'"}},
      {tri + "f 1 2 -3000000000\n", {"line 4", "face indices"}},
      {tri + "f 1/x 2 3\n", {"line 4", "face indices", "'1/x'"}},
  };
  for (const auto& c : cases) {
    const std::string path = write_file("bad.obj", c.text);
    const std::string msg = error_of([&] { load_mesh(path); });
    EXPECT_TRUE(test::Contains(msg, {path + ": "})) << c.text;
    for (const auto& part : c.parts) EXPECT_TRUE(test::Contains(msg, {part})) << c.text;
  }
}

// "Kd nan" or "Kd -1" would render black without a word (issue 14).
TEST(MeshObj, BadMaterialValuesAreErrorsNamingTheLibraryAndLine) {
  for (const char* bad : {"Kd nan 0 0", "Kd -1 0 0", "Ks 1 1", "Ns inf", "Ke 0 0 1e39", "d -0.5"}) {
    write_file("m.mtl", "# materials\nnewmtl red\n" + std::string(bad) + "\n");
    const std::string path =
        write_file("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    EXPECT_TRUE(test::Contains(error_of([&] { load_mesh(path); }), {"m.mtl: line 3: ", "finite non-negative"}))
        << bad;
  }
}

TEST(MeshObj, ErrorsNameTheFile) {
  std::string msg = error_of([] { load_mesh(fixture("bad_syntax.obj")); });
  EXPECT_NE(msg.find("bad_syntax.obj"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 4"), std::string::npos) << msg;  // tinyobjloader's own diagnosis

  msg = error_of([] { load_mesh(fixture("out_of_range.obj")); });
  EXPECT_NE(msg.find("out_of_range.obj"), std::string::npos) << msg;
  EXPECT_NE(msg.find("index 9"), std::string::npos) << msg;

  msg = error_of([] { load_mesh(fixture("no_such_file.obj")); });
  EXPECT_NE(msg.find("no_such_file.obj"), std::string::npos) << msg;
  msg = error_of([] { load_mesh(fixture("polygons.stl")); });
  EXPECT_NE(msg.find(".stl"), std::string::npos) << msg;
}

// ---- PLY ----------------------------------------------------------------

// A square pyramid (a quad base and four triangles) with extra properties of
// many types around the ones the reader uses, an unused element before the
// vertices and one after the faces.
struct PlyValue {
  const char* type;
  double value;
};
using PlyRow = std::vector<std::vector<PlyValue>>;  // groups: scalar = 1 value, list = count + items

const char* kPyramidHeaderBody =
    "comment generated by test_mesh\n"
    "element camera 1\n"
    "property float view_px\n"
    "property list uchar double extra\n"
    "element vertex 5\n"
    "property float x\n"
    "property uchar red\n"
    "property float y\n"
    "property float z\n"
    "property double confidence\n"
    "property float nx\n"
    "property float ny\n"
    "property float nz\n"
    "property int16 s16\n"
    "property float32 u\n"
    "property float32 v\n"
    "property uint flags\n"
    "property char c8\n"
    "element face 5\n"
    "property uchar intensity\n"
    "property int8 i8\n"
    "property list uchar int vertex_indices\n"
    "property list ushort float texcoord\n"
    "property float64 quality\n"
    "property uint16 tag\n"
    "element edge 2\n"
    "property int vertex1\n"
    "property uint32 vertex2\n"
    "end_header\n";

std::vector<PlyRow> pyramid_rows() {
  std::vector<PlyRow> rows;
  rows.push_back({{{"float", 1.5}}, {{"uchar", 2}, {"double", 0.25}, {"double", -7}}});
  const float pos[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}, {0.5f, 1, 0.5f}};
  for (int i = 0; i < 5; ++i) {
    const glm::vec3 n = i == 4 ? glm::vec3(0, 1, 0) : glm::normalize(glm::vec3(pos[i][0] - 0.5f, -0.5f, pos[i][2] - 0.5f));
    rows.push_back({{{"float", pos[i][0]}}, {{"uchar", 200.0 + i}}, {{"float", pos[i][1]}}, {{"float", pos[i][2]}},
                    {{"double", 0.1 * i}}, {{"float", n.x}}, {{"float", n.y}}, {{"float", n.z}},
                    {{"int16", -300.0 * i}}, {{"float", pos[i][0]}}, {{"float", pos[i][2]}},
                    {{"uint", 4000000000.0 - i}}, {{"char", -5.0 * i}}});
  }
  const std::vector<std::vector<int>> faces = {{0, 1, 2, 3}, {0, 4, 1}, {1, 4, 2}, {2, 4, 3}, {3, 4, 0}};
  for (size_t f = 0; f < faces.size(); ++f) {
    std::vector<PlyValue> list = {{"uchar", static_cast<double>(faces[f].size())}};
    for (int i : faces[f]) list.push_back({"int", static_cast<double>(i)});
    std::vector<PlyValue> tex = {{"ushort", 2}, {"float", 0.5}, {"float", 0.75}};
    rows.push_back({{{"uchar", 255.0 - f}}, {{"char", -1.0 * f}}, list, tex, {{"double", 1e300}}, {{"ushort", 65535}}});
  }
  rows.push_back({{{"int", 0}}, {{"uint", 4}}});
  rows.push_back({{{"int", 1}}, {{"uint", 4}}});
  return rows;
}

void put(std::string& out, const PlyValue& v, const std::string& format) {
  const std::string t = v.type;
  if (format == "ascii") {
    char buf[64];
    if (t == "float" || t == "double")
      std::snprintf(buf, sizeof buf, "%.17g ", v.value);
    else
      std::snprintf(buf, sizeof buf, "%lld ", static_cast<long long>(v.value));
    out += buf;
    return;
  }
  unsigned char bytes[8];
  size_t n = 0;
  auto raw = [&](const void* p, size_t size) { std::memcpy(bytes, p, n = size); };
  if (t == "char") { int8_t x = static_cast<int8_t>(v.value); raw(&x, 1); }
  else if (t == "uchar") { uint8_t x = static_cast<uint8_t>(v.value); raw(&x, 1); }
  else if (t == "int16") { int16_t x = static_cast<int16_t>(v.value); raw(&x, 2); }
  else if (t == "ushort") { uint16_t x = static_cast<uint16_t>(v.value); raw(&x, 2); }
  else if (t == "int") { int32_t x = static_cast<int32_t>(v.value); raw(&x, 4); }
  else if (t == "uint") { uint32_t x = static_cast<uint32_t>(v.value); raw(&x, 4); }
  else if (t == "float") { float x = static_cast<float>(v.value); raw(&x, 4); }
  else { double x = v.value; raw(&x, 8); }
  if (format == "binary_big_endian") std::reverse(bytes, bytes + n);  // the test host is little-endian
  out.append(reinterpret_cast<const char*>(bytes), n);
}

std::string pyramid_ply(const std::string& format) {
  std::string out = "ply\nformat " + format + " 1.0\n" + kPyramidHeaderBody;
  for (const PlyRow& row : pyramid_rows()) {
    for (const auto& group : row)
      for (const auto& v : group) put(out, v, format);
    if (format == "ascii") out.back() = '\n';
  }
  return out;
}

void expect_pyramid(const Mesh& m) {
  EXPECT_EQ(m.source_faces, 5u);
  EXPECT_EQ(m.dropped_degenerate, 0u);
  ASSERT_EQ(m.triangles.size(), 6u);
  EXPECT_EQ(m.triangles[0].p[0], glm::vec3(0, 0, 0));
  EXPECT_EQ(m.triangles[0].p[1], glm::vec3(1, 0, 0));
  EXPECT_EQ(m.triangles[0].p[2], glm::vec3(1, 0, 1));
  EXPECT_EQ(m.triangles[2].p[1], glm::vec3(0.5f, 1, 0.5f));
  for (const auto& t : m.triangles) {
    EXPECT_TRUE(t.has_normals);
    EXPECT_TRUE(t.has_uvs);
    EXPECT_EQ(t.material, -1);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(t.uv[k], glm::vec2(t.p[k].x, t.p[k].z));
  }
  EXPECT_NEAR(glm::length(m.triangles[0].n[0]), 1.0f, 1e-6f);
}

TEST(MeshPly, AsciiLittleAndBigEndianGiveIdenticalTriangles) {
  const Mesh a = load_mesh(write_file("pyramid_ascii.ply", pyramid_ply("ascii")));
  const Mesh le = load_mesh(write_file("pyramid_le.ply", pyramid_ply("binary_little_endian")));
  const Mesh be = load_mesh(write_file("pyramid_be.ply", pyramid_ply("binary_big_endian")));
  expect_pyramid(a);
  expect_pyramid(le);
  expect_pyramid(be);
  ASSERT_EQ(le.triangles.size(), a.triangles.size());
  ASSERT_EQ(be.triangles.size(), a.triangles.size());
  for (size_t i = 0; i < a.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(le.triangles[i].p[k], a.triangles[i].p[k]);
      EXPECT_EQ(be.triangles[i].p[k], a.triangles[i].p[k]);
      EXPECT_EQ(le.triangles[i].n[k], a.triangles[i].n[k]);
      EXPECT_EQ(be.triangles[i].n[k], a.triangles[i].n[k]);
      EXPECT_EQ(be.triangles[i].uv[k], a.triangles[i].uv[k]);
    }
}

TEST(MeshPly, SingularIndexNameAndStTexcoords) {
  const Mesh m = load_mesh(fixture("quad_st.ply"));
  EXPECT_EQ(m.source_faces, 1u);
  ASSERT_EQ(m.triangles.size(), 2u);
  EXPECT_TRUE(m.triangles[0].has_uvs);
  EXPECT_FALSE(m.triangles[0].has_normals);
  EXPECT_EQ(m.triangles[1].uv[1], glm::vec2(1, 1));
}

TEST(MeshPly, DegenerateDropped) {
  const std::string ply =
      "ply\r\nformat ascii 1.0\r\nelement vertex 4\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n"
      "element face 4\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
      "0 0 0\r\n1 0 0\r\n0 1 0\r\n2 0 0\r\n3 0 1 2\r\n3 0 1 3\r\n3 0 0 2\r\n2 0 1\r\n";
  const Mesh m = load_mesh(write_file("degenerate.ply", ply));
  EXPECT_EQ(m.source_faces, 4u);
  EXPECT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.dropped_degenerate, 3u);
}

// A NaN or infinite value is an error naming the item (and the line in
// ASCII), never a silently dropped triangle (issue 14).
TEST(MeshPly, NonFiniteVertexIsAnError) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (const char* bad : {"nan", "inf", "-inf", "1e40"}) {
    const std::string path =
        write_file("nonfinite.ply", header + "0 0 0\n1 0 0\n0 " + std::string(bad) + " 0\n3 0 1 2\n");
    EXPECT_TRUE(test::Contains(error_of([&] { load_mesh(path); }),
                               {path, "item 3 of 3", "line 12", "expected a finite 'y'"}));
  }
  std::string binary = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                       "property float z\nend_header\n";
  const float v[3] = {0.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f};
  binary.append(reinterpret_cast<const char*>(v), sizeof v);
  const std::string path = write_file("nonfinite_binary.ply", binary);
  EXPECT_TRUE(test::Contains(error_of([&] { load_mesh(path); }), {path, "item 1 of 1", "expected a finite 'y'"}));
}

TEST(MeshPly, TruncatedBinaryIsAnErrorNamingTheFile) {
  const std::string full = pyramid_ply("binary_big_endian");
  // Cutting into the faces (not just the trailing edges) must be caught.
  for (size_t cut : {size_t(10), size_t(40), size_t(150)}) {
    const std::string path = write_file("cut.ply", full.substr(0, full.size() - cut));
    const std::string msg = error_of([&] { load_mesh(path); });
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
  }
  const std::string path = write_file("huge_count.ply",
                                      "ply\nformat binary_little_endian 1.0\nelement vertex 999999999999\n"
                                      "property float x\nproperty float y\nproperty float z\nend_header\n");
  EXPECT_NE(error_of([&] { load_mesh(path); }).find("truncated"), std::string::npos);
}

TEST(MeshPly, OutOfRangeIndexIsAnError) {
  const std::string msg = error_of([] { load_mesh(fixture("bad_index.ply")); });
  EXPECT_NE(msg.find("bad_index.ply"), std::string::npos) << msg;
  EXPECT_NE(msg.find("index 7"), std::string::npos) << msg;
}

TEST(MeshPly, HeaderErrorsNameWhatIsWrong) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 0\n";
  const struct {
    std::string text, expect;
  } cases[] = {
      {"ply\nformat binary_middle_endian 1.0\nend_header\n", "binary_middle_endian"},
      {"ply\nformat ascii 2.0\nend_header\n", "version"},
      {head + "property float16 x\nend_header\n", "float16"},
      {head + "property float x\nproperty float y\nend_header\n", "'z'"},
      {head + "propery float x\nend_header\n", "propery"},
      {"solid cube\n", "not a PLY"},
      {head + "property float x\n", "end_header"},
  };
  for (const auto& c : cases) {
    const std::string path = write_file("header.ply", c.text);
    const std::string msg = error_of([&] { load_mesh(path); });
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(c.expect), std::string::npos) << msg;
  }
}

// ---- Models in ../shared (skipped when absent) ----------------------------

struct Loaded {
  Mesh mesh;
  double ms;
};

Loaded timed_load(const std::string& path) {
  const auto t0 = std::chrono::steady_clock::now();
  Mesh m = load_mesh(path);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("  %s: %zu faces -> %zu triangles, %zu dropped, %.1f ms\n", path.c_str(), m.source_faces,
              m.triangles.size(), m.dropped_degenerate, ms);
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& t : m.triangles)
    for (const auto& p : t.p) lo = glm::min(lo, p), hi = glm::max(hi, p);
  for (int a = 0; a < 3; ++a) {
    EXPECT_TRUE(std::isfinite(lo[a]) && std::isfinite(hi[a])) << path;
    EXPECT_LT(lo[a], hi[a]) << path;
  }
  return {std::move(m), ms};
}

TEST(MeshShared, StanfordScans) {
  CAUSTICA_REQUIRE_SHARED(shared);
  const Loaded arm = timed_load(shared + "/models/armadillo/Armadillo.ply");
  EXPECT_EQ(arm.mesh.source_faces, 345944u);  // "element face 345944" in its header
  EXPECT_EQ(arm.mesh.triangles.size() + arm.mesh.dropped_degenerate, 345944u);
  EXPECT_LT(arm.mesh.dropped_degenerate, 100u);

  for (const char* name : {"/models/bunny/bun_zipper.ply", "/models/bunny/stanford-bunny.obj"}) {
    const Loaded bunny = timed_load(shared + name);
    EXPECT_EQ(bunny.mesh.source_faces, 69451u) << name;
    EXPECT_EQ(bunny.mesh.triangles.size() + bunny.mesh.dropped_degenerate, 69451u) << name;
    EXPECT_LT(bunny.mesh.dropped_degenerate, 20u) << name;
  }
}

TEST(MeshShared, ConferenceSponzaAndCornellBox) {
  CAUSTICA_REQUIRE_SHARED(shared);
  const Loaded conf = timed_load(shared + "/models/conference/conference.obj");
  EXPECT_EQ(conf.mesh.source_faces, 330837u);  // 330,495 triangles + 342 quads
  EXPECT_EQ(conf.mesh.triangles.size() + conf.mesh.dropped_degenerate, 331179u);
  EXPECT_EQ(conf.mesh.materials.size(), 35u);
  for (const auto& w : conf.mesh.warnings) std::printf("  warning: %s\n", w.c_str());

  // Sponza's MTL names textures relative to its folder; the joined paths must exist.
  const Loaded sponza = timed_load(shared + "/models/sponza-dabrovic/sponza.obj");
  EXPECT_EQ(sponza.mesh.source_faces, 40211u);  // 13,972 triangles + 26,239 quads
  EXPECT_EQ(sponza.mesh.triangles.size() + sponza.mesh.dropped_degenerate, 66450u);
  size_t textured = 0;
  for (const auto& m : sponza.mesh.materials)
    if (!m.diffuse_texture.empty()) {
      ++textured;
      EXPECT_TRUE(std::filesystem::exists(m.diffuse_texture)) << m.diffuse_texture;
    }
  EXPECT_GT(textured, 0u);

  const Loaded box = timed_load(shared + "/models/cornell-box/CornellBox-Original.obj");
  EXPECT_EQ(box.mesh.source_faces, 18u);
  EXPECT_EQ(box.mesh.triangles.size(), 36u);
  EXPECT_EQ(box.mesh.materials.size(), 8u);
  EXPECT_TRUE(box.mesh.warnings.empty());
  bool light = false;
  for (const auto& m : box.mesh.materials) light = light || m.ke == glm::vec3(17, 12, 4);
  EXPECT_TRUE(light);
}

// An inline mesh (scenes/FORMAT.md: "vertices", "indices", "normals",
// "uvs"; what the Python module's load_dict gives NumPy arrays as) places
// the triangles, normals and UVs the same mesh as an OBJ file places, and
// its errors name the entry.
TEST(MeshInline, PlacesWhatTheObjFilePlaces) {
  const std::string dir = test::temp_dir();
  write_file("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                         "vn 0 0 1\nvn 0 0.6 0.8\nvn 0 0 1\nvn 0.6 0 0.8\nf 1/1/1 2/2/2 3/3/3\nf 1/1/1 3/3/3 4/4/4\n");
  auto scene_with = [](const std::string& mesh) {
    return R"({"camera": {"type": "pinhole", "width": 8, "height": 8, "position": [0, 0, -3], "lookAt": [0, 0, 0],
               "upVector": [0, 1, 0], "fov": 45},
               "scene": {"lightsources": [{"type": "pointlight", "position": [0, 2, -2], "intensity": [1, 1, 1]}],
               "shapes": [{"type": "mesh", "transform": {"translate": [0.5, 0, 0], "rotate": [0, 20, 0], "scale": 2}, )" +
           mesh + "}]}}";
  };
  const Scene from_file = parse_scene_text(scene_with(R"("file": "quad.obj")"), "file.json", dir);
  const Scene from_arrays = parse_scene_text(
      scene_with(R"("vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0.5], [0, 1, 0]], "indices": [[0, 1, 2], [0, 2, 3]],
                    "uvs": [[0, 0], [1, 0], [1, 1], [0, 1]],
                    "normals": [[0, 0, 1], [0, 0.6, 0.8], [0, 0, 1], [0.6, 0, 0.8]])"),
      "inline.json", dir);
  ASSERT_EQ(from_file.triangles.size(), 2u);
  ASSERT_EQ(from_arrays.triangles.size(), 2u);
  ASSERT_EQ(from_arrays.triangle_shading.size(), 2u);
  EXPECT_EQ(0, std::memcmp(from_file.triangles.data(), from_arrays.triangles.data(), 2 * sizeof(Triangle)));
  EXPECT_EQ(0, std::memcmp(from_file.triangle_shading.data(), from_arrays.triangle_shading.data(),
                           2 * sizeof(TriangleShading)));
  ASSERT_EQ(from_arrays.meshes.size(), 1u);
  EXPECT_EQ(from_arrays.meshes[0].file, "");  // no file: the scene's own data (scene_hash skips it)
  // A flat index list is the same mesh.
  const Scene flat = parse_scene_text(
      scene_with(R"("vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0.5], [0, 1, 0]], "indices": [0, 1, 2, 0, 2, 3])"),
      "flat.json", dir);
  ASSERT_EQ(flat.triangles.size(), 2u);
  EXPECT_EQ(0, std::memcmp(&flat.triangles[0].v0, &from_file.triangles[0].v0, 3 * sizeof(flat.triangles[0].v0)));

  const std::string v = R"("vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], )";
  EXPECT_NE(error_of([&] { parse_scene_text(scene_with(v + R"("indices": [[0, 1, 3]])"), "s.json", dir); })
                .find("s.json: /scene/shapes/0/indices/0/2: expected an integer in [0, 2], got 3"),
            std::string::npos);
  EXPECT_NE(error_of([&] { parse_scene_text(scene_with(v + R"("indices": [[0, 1, 2]], "uvs": [[0, 0]])"), "s.json", dir); })
                .find("/scene/shapes/0/uvs: expected one entry per vertex (3), got 1"),
            std::string::npos);
  EXPECT_NE(error_of([&] { parse_scene_text(scene_with(R"("indices": [[0, 1, 2]])"), "s.json", dir); })
                .find("/scene/shapes/0/indices: belongs to an inline mesh"),
            std::string::npos);
  EXPECT_NE(error_of([&] { parse_scene_text(scene_with(v + R"("file": "quad.obj", "indices": [0, 1, 2])"), "s.json", dir); })
                .find("expected either \"vertices\" (an inline mesh) or \"file\""),
            std::string::npos);
}

}  // namespace
}  // namespace caustica
