// Scene loading: glTF files written by the tests, the real scenes, and the built-in scene.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "../skip_unless_ci.h"
#include <nlohmann/json.hpp>

#include "scene/builtin_scene.h"
#include "scene/gltf_loader.h"
#include "util/error.h"

namespace rtusim {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Tri = std::array<uint32_t, 3>;

constexpr int kByte = 5121;
constexpr int kUShort = 5123;
constexpr int kUInt = 5125;
constexpr int kFloat = 5126;

std::string base64(const std::vector<uint8_t>& data) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < data.size(); i += 3) {
    uint32_t v = static_cast<uint32_t>(data[i]) << 16;
    if (i + 1 < data.size()) v |= static_cast<uint32_t>(data[i + 1]) << 8;
    if (i + 2 < data.size()) v |= data[i + 2];
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < data.size() ? table[(v >> 6) & 63] : '=';
    out += i + 2 < data.size() ? table[v & 63] : '=';
  }
  return out;
}

// Builds a small glTF document with one binary buffer, written as .gltf or .glb.
class GltfBuilder {
 public:
  GltfBuilder() { doc["asset"] = {{"version", "2.0"}}; }

  // Appends raw bytes (4-byte aligned) and a buffer view over them.
  int view(const void* data, size_t bytes, size_t stride = 0) {
    while (bin.size() % 4) bin.push_back(0);
    const size_t offset = bin.size();
    const auto* p = static_cast<const uint8_t*>(data);
    bin.insert(bin.end(), p, p + bytes);
    json v = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
    if (stride) v["byteStride"] = stride;
    doc["bufferViews"].push_back(v);
    return static_cast<int>(doc["bufferViews"].size() - 1);
  }
  int accessor(int view_index, size_t offset, int component_type, size_t count, const std::string& type) {
    doc["accessors"].push_back({{"bufferView", view_index}, {"byteOffset", offset},
                                {"componentType", component_type}, {"count", count}, {"type", type}});
    return static_cast<int>(doc["accessors"].size() - 1);
  }
  int vec3s(const std::vector<glm::vec3>& v) {
    return accessor(view(v.data(), v.size() * sizeof(glm::vec3)), 0, kFloat, v.size(), "VEC3");
  }
  int indices(const std::vector<uint32_t>& idx, int component_type) {
    std::vector<uint8_t> bytes;
    for (uint32_t i : idx) {
      const size_t n = component_type == kByte ? 1 : component_type == kUShort ? 2 : 4;
      for (size_t b = 0; b < n; ++b) bytes.push_back(static_cast<uint8_t>(i >> (8 * b)));
    }
    return accessor(view(bytes.data(), bytes.size()), 0, component_type, idx.size(), "SCALAR");
  }
  // A mesh with one primitive per entry of `prims` (each a JSON primitive object).
  int mesh(const std::string& name, const json& prims) {
    doc["meshes"].push_back({{"name", name}, {"primitives", prims}});
    return static_cast<int>(doc["meshes"].size() - 1);
  }
  // A one-triangle-list mesh from positions (and optional indices).
  int simple_mesh(const std::string& name, const std::vector<glm::vec3>& pos,
                  const std::vector<uint32_t>& idx = {}) {
    json prim = {{"attributes", {{"POSITION", vec3s(pos)}}}};
    if (!idx.empty()) prim["indices"] = indices(idx, kUInt);
    return mesh(name, json::array({prim}));
  }
  int node(const json& n) {
    doc["nodes"].push_back(n);
    return static_cast<int>(doc["nodes"].size() - 1);
  }
  void scene(const std::vector<int>& roots) {
    doc["scenes"] = json::array({{{"nodes", roots}}});
    doc["scene"] = 0;
  }

  // .gltf with the buffer as a data URI (or an external .bin next to it).
  std::string write_gltf(const fs::path& path, bool external_bin = false) {
    json d = doc;
    if (!bin.empty()) {
      std::string uri = "data:application/octet-stream;base64," + base64(bin);
      if (external_bin) {
        uri = path.stem().string() + ".bin";
        std::ofstream(path.parent_path() / uri, std::ios::binary)
            .write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
      }
      d["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", uri}}});
    }
    std::ofstream(path) << d.dump(1);
    return path.string();
  }
  // .glb: a JSON chunk and a BIN chunk holding buffer 0.
  std::string write_glb(const fs::path& path) {
    json d = doc;
    std::vector<uint8_t> b = bin;
    while (b.size() % 4) b.push_back(0);
    if (!bin.empty()) d["buffers"] = json::array({{{"byteLength", bin.size()}}});
    std::string text = d.dump();
    while (text.size() % 4) text += ' ';
    std::vector<uint8_t> out;
    auto u32 = [&](uint32_t v) {
      for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
    };
    const uint32_t total = 12 + 8 + static_cast<uint32_t>(text.size()) + (b.empty() ? 0 : 8 + static_cast<uint32_t>(b.size()));
    u32(0x46546C67);
    u32(2);
    u32(total);
    u32(static_cast<uint32_t>(text.size()));
    u32(0x4E4F534A);
    out.insert(out.end(), text.begin(), text.end());
    if (!b.empty()) {
      u32(static_cast<uint32_t>(b.size()));
      u32(0x004E4942);
      out.insert(out.end(), b.begin(), b.end());
    }
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(out.size()));
    return path.string();
  }

  json doc;
  std::vector<uint8_t> bin;
};

const std::vector<glm::vec3> kTriangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

void expect_near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, eps) << "x";
  EXPECT_NEAR(a.y, b.y, eps) << "y";
  EXPECT_NEAR(a.z, b.z, eps) << "z";
}

glm::vec3 geometric_normal(const Scene& s, uint32_t tri) {
  const auto v = s.vertices(tri);
  return glm::cross(v[1] - v[0], v[2] - v[0]);
}

class SceneLoaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("rtusim_scene_" + std::string(info->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Loads a one-node file whose node is `node_json` plus the one-triangle mesh 0.
  Scene load_transformed(json node_json, const std::vector<glm::vec3>& pos = kTriangle) {
    GltfBuilder b;
    b.simple_mesh("tri", pos);
    node_json["mesh"] = 0;
    b.scene({b.node(node_json)});
    return load_gltf(b.write_gltf(dir_ / "t.gltf"));
  }

  // Expects load_gltf(path) to throw InputError with a one-line message naming the file and
  // containing `what`.
  void expect_input_error(const std::string& path, const std::string& what) {
    try {
      load_gltf(path);
      ADD_FAILURE() << "no InputError for " << path;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(fs::path(path).filename().string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(what), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  }

  fs::path dir_;
};

TEST_F(SceneLoaderTest, TranslationMovesVertices) {
  const Scene s = load_transformed({{"translation", {1, 2, 3}}});
  ASSERT_EQ(s.triangle_count(), 1u);
  expect_near(s.positions[s.triangles[0][0]], {1, 2, 3});
  expect_near(s.positions[s.triangles[0][1]], {2, 2, 3});
}

TEST_F(SceneLoaderTest, RotationQuaternionXYZW) {
  // 90 degrees about +Z: x -> y.
  const float h = std::sqrt(0.5f);
  const Scene s = load_transformed({{"rotation", {0, 0, h, h}}});
  expect_near(s.positions[s.triangles[0][1]], {0, 1, 0});
  expect_near(s.positions[s.triangles[0][2]], {-1, 0, 0});
}

TEST_F(SceneLoaderTest, ScaleAndTRSOrder) {
  const Scene scaled = load_transformed({{"scale", {2, 3, 4}}}, {{1, 1, 1}, {1, 0, 0}, {0, 1, 0}});
  expect_near(scaled.positions[scaled.triangles[0][0]], {2, 3, 4});
  // T * R * S applied to (1,0,0): S -> (2,0,0), R (90 deg about Z) -> (0,2,0), T -> (1,4,3).
  const float h = std::sqrt(0.5f);
  const Scene trs = load_transformed({{"translation", {1, 2, 3}}, {"rotation", {0, 0, h, h}}, {"scale", {2, 1, 1}}});
  expect_near(trs.positions[trs.triangles[0][1]], {1, 4, 3});
}

TEST_F(SceneLoaderTest, MatrixIsColumnMajor) {
  // Scale 2 in x, translation (5, 6, 7) in elements 12..14.
  const Scene s = load_transformed({{"matrix", {2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 6, 7, 1}}});
  expect_near(s.positions[s.triangles[0][0]], {5, 6, 7});
  expect_near(s.positions[s.triangles[0][1]], {7, 6, 7});
}

TEST_F(SceneLoaderTest, NestedWorldIsParentTimesChild) {
  GltfBuilder b;
  b.simple_mesh("tri", kTriangle);
  const int child = b.node({{"translation", {1, 0, 0}}, {"mesh", 0}});
  const int parent = b.node({{"translation", {10, 0, 0}}, {"scale", {2, 2, 2}}, {"children", {child}}});
  b.scene({parent});
  const Scene s = load_gltf(b.write_gltf(dir_ / "nested.gltf"));
  // parent * child * (1,0,0) = T10 S2 (2,0,0) = (14,0,0); child * parent would give (13,0,0).
  expect_near(s.positions[s.triangles[0][0]], {12, 0, 0});
  expect_near(s.positions[s.triangles[0][1]], {14, 0, 0});
}

TEST_F(SceneLoaderTest, MirroringTransformFlipsWinding) {
  const Scene plain = load_transformed(json::object());
  EXPECT_GT(geometric_normal(plain, 0).z, 0.0f);
  const Scene mirrored = load_transformed({{"scale", {-1, 1, 1}}});
  const Tri t = mirrored.triangles[0];
  EXPECT_EQ(t[0], 0u);
  EXPECT_EQ(t[1], 2u);
  EXPECT_EQ(t[2], 1u);
  EXPECT_GT(geometric_normal(mirrored, 0).z, 0.0f);
}

TEST_F(SceneLoaderTest, NormalsUseInverseTransposeAndDefaultToZero) {
  GltfBuilder b;
  const float r = std::sqrt(0.5f);
  const int pos = b.vec3s(kTriangle);
  const int nrm = b.vec3s({{r, r, 0}, {r, r, 0}, {0, 0, 1}});
  b.mesh("with_normals", json::array({{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}}}}}));
  b.simple_mesh("without", kTriangle);
  b.scene({b.node({{"mesh", 0}, {"scale", {2, 1, 1}}}), b.node({{"mesh", 1}})});
  const Scene s = load_gltf(b.write_gltf(dir_ / "normals.gltf"));
  ASSERT_EQ(s.normals.size(), s.positions.size());
  // Inverse transpose of diag(2,1,1) maps (1,1,0) to (0.5,1,0).
  expect_near(s.normals[s.triangles[0][0]], glm::normalize(glm::vec3(0.5f, 1.0f, 0.0f)));
  expect_near(s.normals[s.triangles[0][2]], {0, 0, 1});
  expect_near(s.normals[s.triangles[1][0]], {0, 0, 0});
}

TEST_F(SceneLoaderTest, NormalizedByteNormals) {
  // Quantized normals: normalized signed bytes, padded to a 4-byte stride.
  GltfBuilder b;
  const int p = b.vec3s(kTriangle);
  const std::vector<int8_t> n = {127, 0, 0, 0, 0, -127, 0, 0, 0, 0, 127, 0};
  const int na = b.accessor(b.view(n.data(), n.size(), 4), 0, 5120, 3, "VEC3");
  b.doc["accessors"][na]["normalized"] = true;
  b.mesh("q", json::array({{{"attributes", {{"POSITION", p}, {"NORMAL", na}}}}}));
  b.scene({b.node({{"mesh", 0}})});
  const Scene s = load_gltf(b.write_gltf(dir_ / "quantized.gltf"));
  expect_near(s.normals[0], {1, 0, 0});
  expect_near(s.normals[1], {0, -1, 0});
  expect_near(s.normals[2], {0, 0, 1});
}

TEST_F(SceneLoaderTest, TriangleStripAndFanUnrolled) {
  GltfBuilder b;
  std::vector<glm::vec3> pos;
  for (int i = 0; i < 5; ++i) pos.push_back({static_cast<float>(i), static_cast<float>(i % 2), 0});
  const int p = b.vec3s(pos);
  const int rev = b.indices({4, 3, 2, 1, 0}, kUShort);
  b.mesh("strip", json::array({{{"attributes", {{"POSITION", p}}}, {"mode", 5}}}));
  b.mesh("fan", json::array({{{"attributes", {{"POSITION", p}}}, {"mode", 6}}}));
  b.mesh("strip_indexed", json::array({{{"attributes", {{"POSITION", p}}}, {"mode", 5}, {"indices", rev}}}));
  b.scene({b.node({{"mesh", 0}}), b.node({{"mesh", 1}}), b.node({{"mesh", 2}})});
  const Scene s = load_gltf(b.write_gltf(dir_ / "strips.gltf"));
  ASSERT_EQ(s.triangle_count(), 9u);
  // glTF spec: strip p_i = {v_i, v_{i+1+i%2}, v_{i+2-i%2}}; fan p_i = {v_{i+1}, v_{i+2}, v_0}.
  const std::vector<Tri> expected = {{0, 1, 2}, {1, 3, 2}, {2, 3, 4},     // strip, base 0
                                     {6, 7, 5}, {7, 8, 5}, {8, 9, 5},     // fan, base 5
                                     {14, 13, 12}, {13, 11, 12}, {12, 11, 10}};  // reversed strip, base 10
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(s.triangles[i], expected[i]) << "triangle " << i;
}

TEST_F(SceneLoaderTest, IndexComponentTypes) {
  const std::vector<glm::vec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<uint32_t> idx = {0, 1, 2, 0, 2, 3};
  for (int type : {kByte, kUShort, kUInt}) {
    GltfBuilder b;
    const int p = b.vec3s(quad);
    b.mesh("quad", json::array({{{"attributes", {{"POSITION", p}}}, {"indices", b.indices(idx, type)}}}));
    b.scene({b.node({{"mesh", 0}})});
    const Scene s = load_gltf(b.write_gltf(dir_ / ("idx" + std::to_string(type) + ".gltf")));
    ASSERT_EQ(s.triangle_count(), 2u) << type;
    EXPECT_EQ(s.triangles[0], (Tri{0, 1, 2})) << type;
    EXPECT_EQ(s.triangles[1], (Tri{0, 2, 3})) << type;
  }
}

TEST_F(SceneLoaderTest, InterleavedStrideAndOffsets) {
  // 8 leading pad bytes, then per vertex: position (12 B), normal (12 B), 4 pad bytes.
  GltfBuilder b;
  std::vector<float> data(2, -99.0f);
  const std::vector<glm::vec3> pos = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}};
  for (const auto& p : pos) data.insert(data.end(), {p.x, p.y, p.z, 0, 0, 1, -99});
  const int v = b.view(data.data(), data.size() * 4, 28);
  // Rebase the view past the padding: the view starts at byte 8 of the data.
  b.doc["bufferViews"][v]["byteOffset"] = 8;
  b.doc["bufferViews"][v]["byteLength"] = data.size() * 4 - 8;
  const int pa = b.accessor(v, 0, kFloat, 3, "VEC3");
  const int na = b.accessor(v, 12, kFloat, 3, "VEC3");
  b.mesh("interleaved", json::array({{{"attributes", {{"POSITION", pa}, {"NORMAL", na}}}}}));
  b.scene({b.node({{"mesh", 0}})});
  const Scene s = load_gltf(b.write_gltf(dir_ / "interleaved.gltf"));
  ASSERT_EQ(s.triangle_count(), 1u);
  for (int i = 0; i < 3; ++i) {
    expect_near(s.positions[s.triangles[0][i]], pos[i]);
    expect_near(s.normals[s.triangles[0][i]], {0, 0, 1});
  }
}

TEST_F(SceneLoaderTest, NonIndexedTriangles) {
  GltfBuilder b;
  std::vector<glm::vec3> pos;
  for (int i = 0; i < 7; ++i) pos.push_back({static_cast<float>(i), 0, 0});
  b.simple_mesh("list", pos);
  b.scene({b.node({{"mesh", 0}})});
  const Scene s = load_gltf(b.write_gltf(dir_ / "nonindexed.gltf"));
  ASSERT_EQ(s.triangle_count(), 2u);  // the 7th vertex is left over
  EXPECT_EQ(s.triangles[0], (Tri{0, 1, 2}));
  EXPECT_EQ(s.triangles[1], (Tri{3, 4, 5}));
}

TEST_F(SceneLoaderTest, MaterialFactorsAndExtensions) {
  GltfBuilder b;
  const int p = b.vec3s(kTriangle);
  b.doc["materials"] = json::array(
      {{{"name", "glassy"},
        {"pbrMetallicRoughness", {{"baseColorFactor", {0.1, 0.2, 0.3, 1.0}}, {"metallicFactor", 0.25}, {"roughnessFactor", 0.5}}},
        {"emissiveFactor", {0.5, 0.25, 1.0}},
        {"extensions",
         {{"KHR_materials_transmission", {{"transmissionFactor", 0.75}}},
          {"KHR_materials_ior", {{"ior", 1.33}}},
          {"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}}},
       {{"name", "plain"}}});
  b.mesh("m", json::array({{{"attributes", {{"POSITION", p}}}, {"material", 0}},
                           {{"attributes", {{"POSITION", p}}}},
                           {{"attributes", {{"POSITION", p}}}, {"material", 1}},
                           {{"attributes", {{"POSITION", p}}}}}));
  b.scene({b.node({{"mesh", 0}})});
  const Scene s = load_gltf(b.write_gltf(dir_ / "materials.gltf"));
  ASSERT_EQ(s.materials.size(), 3u);  // two from the file, one glTF default appended once
  const Material& m = s.materials[0];
  EXPECT_EQ(m.name, "glassy");
  expect_near(m.base_color, {0.1f, 0.2f, 0.3f});
  EXPECT_FLOAT_EQ(m.metallic, 0.25f);
  EXPECT_FLOAT_EQ(m.roughness, 0.5f);
  expect_near(m.emissive, {2.0f, 1.0f, 4.0f});
  EXPECT_FLOAT_EQ(m.transmission, 0.75f);
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  const Material& plain = s.materials[1];
  EXPECT_FLOAT_EQ(plain.ior, 1.5f);
  EXPECT_FLOAT_EQ(plain.transmission, 0.0f);
  const Material& def = s.materials[2];
  EXPECT_FLOAT_EQ(def.metallic, 1.0f);
  EXPECT_FLOAT_EQ(def.roughness, 1.0f);
  expect_near(def.base_color, {1, 1, 1});
  EXPECT_EQ(s.triangle_material, (std::vector<uint32_t>{0, 2, 1, 2}));
}

TEST_F(SceneLoaderTest, PunctualPointLightAtNodeWorldPosition) {
  GltfBuilder b;
  b.simple_mesh("tri", kTriangle);
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array(
      {{{"type", "point"}, {"name", "bulb"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 3.0}},
       {{"type", "directional"}, {"name", "sun"}}});
  const int bulb = b.node({{"translation", {0, 1, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  const int sun = b.node({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  b.scene({b.node({{"mesh", 0}, {"translation", {2, 0, 0}}, {"children", {bulb, sun}}})});
  const Scene s = load_gltf(b.write_gltf(dir_ / "light.gltf"));
  ASSERT_EQ(s.lights.size(), 1u);  // the directional light is skipped
  EXPECT_EQ(s.lights[0].name, "bulb");
  expect_near(s.lights[0].position, {2, 1, 0});
  expect_near(s.lights[0].color, {1.0f, 0.5f, 0.25f});
  EXPECT_FLOAT_EQ(s.lights[0].intensity, 3.0f);
}

TEST_F(SceneLoaderTest, CameraFromNode) {
  GltfBuilder b;
  b.simple_mesh("tri", kTriangle);
  b.doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.01}}}}});
  // 90 degrees about +Y turns the camera's -Z view direction into -X.
  const float h = std::sqrt(0.5f);
  b.scene({b.node({{"mesh", 0}}), b.node({{"name", "side"}, {"camera", 0}, {"translation", {0, 0, 5}}, {"rotation", {0, h, 0, h}}}),
           b.node({{"name", "front"}, {"camera", 0}, {"translation", {1, 2, 3}}})});
  const Scene s = load_gltf(b.write_gltf(dir_ / "camera.gltf"));
  ASSERT_EQ(s.cameras.size(), 2u);
  EXPECT_EQ(s.cameras[0].name, "side");
  expect_near(s.cameras[0].eye, {0, 0, 5});
  expect_near(s.cameras[0].target, {-1, 0, 5});
  expect_near(s.cameras[0].up, {0, 1, 0});
  EXPECT_NEAR(s.cameras[0].vfov_deg, 0.5f * 180.0f / 3.14159265f, 1e-4f);
  EXPECT_EQ(s.cameras[1].name, "front");
  expect_near(s.cameras[1].eye, {1, 2, 3});
  expect_near(s.cameras[1].target, {1, 2, 2});
}

// A camera far from the origin keeps its view direction (a unit step ahead of an eye at 1e6
// rounded to a target ~1 degree off; at 3e7 to the eye itself, and the camera was refused).
TEST_F(SceneLoaderTest, FarCameraKeepsItsDirection) {
  for (const double d : {100.0, 1e6, 3e7}) {
    GltfBuilder b;
    b.simple_mesh("tri", kTriangle);
    b.doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.01}}}}});
    // Turned 30 degrees about +Y: the view direction -Z becomes (-sin 30, 0, -cos 30).
    const double half = 15.0 * 3.14159265358979 / 180.0;
    b.scene({b.node({{"mesh", 0}}),
             b.node({{"name", "far"}, {"camera", 0}, {"translation", {d, 0.2 * d, 0.3 * d}},
                     {"rotation", {0.0, std::sin(half), 0.0, std::cos(half)}}})});
    const Scene s = load_gltf(b.write_gltf(dir_ / "far.gltf"));
    ASSERT_EQ(s.cameras.size(), 1u);
    const glm::dvec3 f = glm::normalize(glm::dvec3(s.cameras[0].target) - glm::dvec3(s.cameras[0].eye));
    const glm::dvec3 want(-std::sin(2 * half), 0.0, -std::cos(2 * half));
    EXPECT_LT(std::acos(std::min(1.0, glm::dot(f, want))), 1e-5) << "view direction off at " << d;
    // Near the origin the target stays one unit ahead (the profile layout turns about it).
    const double step = glm::length(glm::dvec3(s.cameras[0].target) - glm::dvec3(s.cameras[0].eye));
    if (d < 1000.0) EXPECT_NEAR(step, 1.0, 1e-3) << "eye at " << d;
  }
}

// Material factors outside the glTF spec's ranges (an ior below 1 made a Fresnel reflectance
// of 25), a required extension the loader does not read, and vertices beyond 1e18 (the
// triangle test's products overflow) are refused, naming what is wrong.
TEST_F(SceneLoaderTest, OutOfRangeFactorsExtensionsAndCoordinatesAreRefused) {
  const auto with_material = [&](const std::string& name, json material) {
    GltfBuilder b;
    const int p = b.vec3s(kTriangle);
    b.doc["materials"] = json::array({material});
    b.mesh("m", json::array({{{"attributes", {{"POSITION", p}}}, {"material", 0}}}));
    b.scene({b.node({{"mesh", 0}})});
    return b.write_gltf(dir_ / name);
  };
  expect_input_error(with_material("ior.gltf", json::parse(R"({"name": "bad glass",
                       "extensions": {"KHR_materials_ior": {"ior": -1.5}}})")),
                     "material 0 'bad glass': ior -1.5");
  expect_input_error(with_material("metal.gltf", json::parse(R"({"pbrMetallicRoughness":
                       {"metallicFactor": 5.0}})")),
                     "material 0: metallicFactor 5");
  expect_input_error(with_material("colour.gltf", json::parse(R"({"pbrMetallicRoughness":
                       {"baseColorFactor": [-0.5, 0.2, 0.2, 1.0]}})")),
                     "baseColorFactor -0.5");
  expect_input_error(with_material("transmission.gltf", json::parse(R"({"extensions":
                       {"KHR_materials_transmission": {"transmissionFactor": 2.0}}})")),
                     "transmissionFactor 2");
  GltfBuilder b;
  b.simple_mesh("tri", kTriangle);
  b.scene({b.node({{"mesh", 0}})});
  b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  expect_input_error(b.write_gltf(dir_ / "draco.gltf"), "requires extension KHR_draco_mesh_compression");
  GltfBuilder far;
  far.simple_mesh("tri", {{0, 0, 0}, {2e18f, 0, 0}, {0, 1, 0}});
  far.scene({far.node({{"mesh", 0}})});
  expect_input_error(far.write_gltf(dir_ / "huge.gltf"), "element 1 lies beyond +-1e18");
}

// Each mesh's triangles sit at x = their expected id, so the id order is visible in positions.
TEST_F(SceneLoaderTest, TriangleIdsFollowLoadOrder) {
  GltfBuilder b;
  auto tri_at = [](float x) { return std::vector<glm::vec3>{{x, 0, 0}, {x, 1, 0}, {x, 0, 1}}; };
  const int p0 = b.vec3s(tri_at(0));
  std::vector<glm::vec3> two = tri_at(1);
  for (const auto& v : tri_at(2)) two.push_back(v);
  const int p12 = b.vec3s(two);
  // Nodes deliberately out of index order: roots are A (node 4) and D (node 0).
  b.mesh("D", json::array({{{"attributes", {{"POSITION", b.vec3s(tri_at(6))}}}}}));
  b.mesh("A", json::array({{{"attributes", {{"POSITION", p0}}}}, {{"attributes", {{"POSITION", p12}}}}}));
  b.mesh("B", json::array({{{"attributes", {{"POSITION", b.vec3s(tri_at(3))}}}}}));
  b.mesh("E", json::array({{{"attributes", {{"POSITION", b.vec3s(tri_at(4))}}}}}));
  b.mesh("C", json::array({{{"attributes", {{"POSITION", b.vec3s(tri_at(5))}}}}}));
  const int d = b.node({{"name", "D"}, {"mesh", 0}});
  const int c = b.node({{"name", "C"}, {"mesh", 4}});
  const int e = b.node({{"name", "E"}, {"mesh", 3}});
  const int bn = b.node({{"name", "B"}, {"mesh", 2}, {"children", {e}}});
  const int a = b.node({{"name", "A"}, {"mesh", 1}, {"children", {bn, c}}});
  b.scene({a, d});
  const Scene s = load_gltf(b.write_gltf(dir_ / "order.gltf"));
  ASSERT_EQ(s.triangle_count(), 7u);
  for (uint32_t i = 0; i < 7; ++i) EXPECT_FLOAT_EQ(s.vertices(i)[0].x, static_cast<float>(i)) << "triangle " << i;

  // Without a scene, the roots are the parentless nodes in index order: D (0) then A (4).
  b.doc.erase("scenes");
  b.doc.erase("scene");
  const Scene no_scene = load_gltf(b.write_gltf(dir_ / "noscene.gltf"));
  ASSERT_EQ(no_scene.triangle_count(), 7u);
  EXPECT_FLOAT_EQ(no_scene.vertices(0)[0].x, 6.0f);
  EXPECT_FLOAT_EQ(no_scene.vertices(1)[0].x, 0.0f);
}

TEST_F(SceneLoaderTest, GlbLoadsLikeGltf) {
  GltfBuilder b;
  const float h = std::sqrt(0.5f);
  b.simple_mesh("quad", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {0, 1, 2, 0, 2, 3});
  b.scene({b.node({{"mesh", 0}, {"rotation", {h, 0, 0, h}}, {"translation", {1, 2, 3}}})});
  const Scene text = load_gltf(b.write_gltf(dir_ / "same.gltf", /*external_bin=*/true));
  const Scene binary = load_gltf(b.write_glb(dir_ / "same.GLB"));
  ASSERT_EQ(binary.triangle_count(), 2u);
  EXPECT_EQ(binary.triangles, text.triangles);
  ASSERT_EQ(binary.positions.size(), text.positions.size());
  for (size_t i = 0; i < text.positions.size(); ++i) expect_near(binary.positions[i], text.positions[i]);
  EXPECT_EQ(binary.source, (dir_ / "same.GLB").string());
}

TEST_F(SceneLoaderTest, TexturesAreNeverDecoded) {
  GltfBuilder b;
  b.simple_mesh("tri", kTriangle);
  // One missing image file and one data URI with bytes no decoder accepts.
  b.doc["images"] = json::array({{{"uri", "missing.png"}}, {{"uri", "data:image/png;base64," + base64({1, 2, 3, 4, 5, 6})}}});
  b.doc["textures"] = json::array({{{"source", 0}}, {{"source", 1}}});
  b.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}}});
  b.doc["meshes"][0]["primitives"][0]["material"] = 0;
  b.scene({b.node({{"mesh", 0}})});
  const Scene s = load_gltf(b.write_gltf(dir_ / "textured.gltf"));
  EXPECT_EQ(s.triangle_count(), 1u);
}

TEST_F(SceneLoaderTest, BadFilesGiveInputErrorNamingTheFile) {
  expect_input_error((dir_ / "nowhere.gltf").string(), "not found");
  {
    const auto path = dir_ / "scene.obj";
    std::ofstream(path) << "v 0 0 0\n";
    expect_input_error(path.string(), "extension");
  }
  {
    const auto path = dir_ / "badjson.gltf";
    std::ofstream(path) << "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [ ";
    expect_input_error(path.string(), "cannot parse");
  }
  {
    GltfBuilder b;
    b.simple_mesh("tri", kTriangle);
    b.scene({b.node({{"mesh", 0}})});
    const auto path = b.write_gltf(dir_ / "nobin.gltf", true);
    fs::remove(dir_ / "nobin.bin");
    expect_input_error(path, "nobin.bin");
  }
  {
    GltfBuilder b;
    b.simple_mesh("tri", kTriangle);
    b.scene({b.node({{"mesh", 0}})});
    const auto path = b.write_gltf(dir_ / "short.gltf", true);
    fs::resize_file(dir_ / "short.bin", 20);
    expect_input_error(path, "short.gltf");
  }
  {
    GltfBuilder b;
    b.simple_mesh("Cube", kTriangle, {0, 1, 7});
    b.scene({b.node({{"mesh", 0}})});
    expect_input_error(b.write_gltf(dir_ / "badindex.gltf"), "index 7 out of range (3 vertices)");
  }
  {
    GltfBuilder b;
    const std::vector<uint16_t> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const int a = b.accessor(b.view(pos.data(), pos.size() * 2), 0, kUShort, 3, "VEC3");
    b.mesh("ints", json::array({{{"attributes", {{"POSITION", a}}}}}));
    b.scene({b.node({{"mesh", 0}})});
    expect_input_error(b.write_gltf(dir_ / "intpos.gltf"), "non-float positions");
  }
  {
    GltfBuilder b;
    b.mesh("lines", json::array({{{"attributes", {{"POSITION", b.vec3s(kTriangle)}}}, {"mode", 1}}}));
    b.scene({b.node({{"mesh", 0}})});
    expect_input_error(b.write_gltf(dir_ / "lines.gltf"), "no triangles");
  }
  {
    GltfBuilder b;
    b.simple_mesh("tri", kTriangle);
    b.scene({b.node({{"mesh", 5}})});
    expect_input_error(b.write_gltf(dir_ / "badmesh.gltf"), "mesh 5 out of range");
  }
  {
    GltfBuilder b;
    b.simple_mesh("tri", kTriangle);
    b.doc["accessors"][0]["count"] = 4;  // 48 bytes from a 36-byte view
    b.scene({b.node({{"mesh", 0}})});
    expect_input_error(b.write_gltf(dir_ / "overrun.gltf"), "overrun");
  }
  {
    GltfBuilder b;
    b.simple_mesh("tri", kTriangle);
    b.doc["bufferViews"][0]["byteLength"] = 400;
    b.scene({b.node({{"mesh", 0}})});
    expect_input_error(b.write_gltf(dir_ / "badview.gltf"), "buffer view 0");
  }
  {
    GltfBuilder b;
    b.simple_mesh("tri", kTriangle);
    b.scene({b.node({{"mesh", 0}, {"children", {9}}})});
    expect_input_error(b.write_gltf(dir_ / "badchild.gltf"), "child 9 out of range");
  }
}

// The real scenes, from the shared scenes folder.
class RealScenesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::is_directory(RTUSIM_SCENES_DEFAULT)) RTUSIM_SKIP_UNLESS_CI("no scenes folder " << RTUSIM_SCENES_DEFAULT);
  }
  static std::string path(const std::string& name) {
    return std::string(RTUSIM_SCENES_DEFAULT) + "/" + name + "/" + name + ".gltf";
  }
  static void expect_bounds(const Scene& s, const glm::vec3& lo, const glm::vec3& hi, float eps) {
    const Bounds3f b = s.bounds();
    expect_near(b.min, lo, eps);
    expect_near(b.max, hi, eps);
  }
};

TEST_F(RealScenesTest, Box) {
  const Scene s = load_gltf(path("box"));
  EXPECT_EQ(s.triangle_count(), 12u);
  expect_bounds(s, glm::vec3(-0.5f), glm::vec3(0.5f), 1e-5f);
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].name, "suggested_camera");
}

TEST_F(RealScenesTest, CornellWhitted) {
  const Scene s = load_gltf(path("cornell_whitted"));
  EXPECT_EQ(s.triangle_count(), 664u);
  expect_bounds(s, glm::vec3(0.0f), glm::vec3(1.0f), 1e-5f);
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].name, "suggested_camera");
  expect_near(s.cameras[0].eye, {0.5f, 0.5f, 2.0f}, 1e-4f);
  expect_near(glm::normalize(s.cameras[0].target - s.cameras[0].eye), {0, 0, -1}, 1e-4f);
  EXPECT_NEAR(s.cameras[0].vfov_deg, 40.0f, 1e-3f);
  int transmissive = 0, metallic = 0;
  for (const Material& m : s.materials) {
    transmissive += m.transmission > 0.0f;
    metallic += m.metallic > 0.5f;
  }
  EXPECT_EQ(transmissive, 1);
  EXPECT_EQ(metallic, 1);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].name, "point_light_suggestion");
  expect_near(s.lights[0].position, {0.5f, 0.95f, 0.5f});
}

TEST_F(RealScenesTest, KitchenAndSponza) {
  const Scene kitchen = load_gltf(path("kitchen"));
  EXPECT_EQ(kitchen.triangle_count(), 110520u);
  expect_bounds(kitchen, {-2.0f, -1.1f, -3.75f}, {6.0f, 2.9f, 4.33f}, 2e-3f);
  EXPECT_EQ(kitchen.lights.size(), 6u);
  const Scene sponza = load_gltf(path("sponza_dabrovic"));
  EXPECT_EQ(sponza.triangle_count(), 66445u);
  expect_bounds(sponza, {-17.403f, -0.907f, -7.799f}, {17.417f, 15.653f, 7.802f}, 2e-3f);
  for (const Scene* s : {&kitchen, &sponza})
    for (uint32_t m : s->triangle_material) ASSERT_LT(m, s->materials.size());
}

TEST_F(RealScenesTest, IridescentDish) {
  const Scene s = load_gltf(path("iridescent_dish"));
  EXPECT_EQ(s.triangle_count(), 24448u);
  expect_bounds(s, {-0.2297f, -0.00003f, -0.2297f}, {0.2297f, 0.2855f, 0.2297f}, 2e-4f);
  int transmissive = 0;
  for (const Material& m : s.materials) transmissive += m.transmission > 0.0f;
  EXPECT_EQ(transmissive, 2);
}

TEST_F(RealScenesTest, MetalRoughSpheresLoadTime) {
  const auto start = std::chrono::steady_clock::now();
  const Scene s = load_gltf(path("metal_rough_spheres"));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "metal_rough_spheres: " << s.triangle_count() << " triangles loaded in " << seconds << " s\n";
  RecordProperty("load_seconds", std::to_string(seconds));
  EXPECT_EQ(s.triangle_count(), 1040213u);
  expect_bounds(s, {-0.000924f, -0.00101f, -0.00335f}, {0.006477f, 0.006494f, 0.00035f}, 2e-6f);
  EXPECT_LT(seconds, 10.0);
}

// Undirected edges of the triangles with material m, each with how many triangles use it, and
// whether every directed edge appears once (consistent winding).
bool closed_and_consistent(const Scene& s, uint32_t material, size_t& triangles) {
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  triangles = 0;
  for (uint32_t t = 0; t < s.triangle_count(); ++t) {
    if (s.triangle_material[t] != material) continue;
    ++triangles;
    for (int e = 0; e < 3; ++e) ++directed[{s.triangles[t][e], s.triangles[t][(e + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    auto back = directed.find({edge.second, edge.first});
    if (count != 1 || back == directed.end() || back->second != 1) return false;
  }
  return triangles > 0;
}

TEST(BuiltinSceneTest, CornellShape) {
  const Scene s = make_builtin_scene("cornell");
  EXPECT_EQ(s.source, "builtin:cornell");
  EXPECT_GE(s.triangle_count(), 2000u);
  EXPECT_LE(s.triangle_count(), 6000u);
  EXPECT_EQ(s.normals.size(), s.positions.size());
  ASSERT_EQ(s.triangle_material.size(), s.triangles.size());
  for (uint32_t m : s.triangle_material) ASSERT_LT(m, s.materials.size());
  for (const auto& t : s.triangles)
    for (uint32_t v : t) ASSERT_LT(v, s.positions.size());
  const Bounds3f bounds = s.bounds();
  expect_near(bounds.min, glm::vec3(0.0f));
  expect_near(bounds.max, glm::vec3(1.0f));
  ASSERT_FALSE(s.lights.empty());
  expect_near(s.lights[0].position, {0.5f, 0.95f, 0.5f});
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].name, "default");
  expect_near(s.cameras[0].eye, {0.5f, 0.5f, 2.0f});
  expect_near(s.cameras[0].target, {0.5f, 0.5f, 0.0f});
  EXPECT_FLOAT_EQ(s.cameras[0].vfov_deg, 40.0f);
  bool emissive = false;
  for (const Material& m : s.materials) emissive |= m.emissive.x > 0.0f;
  EXPECT_TRUE(emissive);
}

TEST(BuiltinSceneTest, MirrorAndGlassAreClosedOutwardSpheres) {
  const Scene s = make_builtin_scene("cornell");
  int mirror = -1, glass = -1;
  for (size_t i = 0; i < s.materials.size(); ++i) {
    if (s.materials[i].metallic >= 0.99f && s.materials[i].roughness == 0.0f) mirror = static_cast<int>(i);
    if (s.materials[i].transmission > 0.99f && s.materials[i].ior == 1.5f) glass = static_cast<int>(i);
  }
  ASSERT_GE(mirror, 0);
  ASSERT_GE(glass, 0);
  for (int m : {mirror, glass}) {
    size_t count = 0;
    EXPECT_TRUE(closed_and_consistent(s, static_cast<uint32_t>(m), count)) << s.materials[m].name;
    EXPECT_GE(count, 1000u);
    EXPECT_LE(count, 2000u);
    // Outward winding and exact normals: the centre is the mean of the sphere's vertices.
    std::set<uint32_t> verts;
    for (uint32_t t = 0; t < s.triangle_count(); ++t)
      if (s.triangle_material[t] == static_cast<uint32_t>(m)) verts.insert(s.triangles[t].begin(), s.triangles[t].end());
    glm::vec3 center(0.0f);
    for (uint32_t v : verts) center += s.positions[v];
    center /= static_cast<float>(verts.size());
    for (uint32_t v : verts) EXPECT_GT(glm::dot(s.normals[v], glm::normalize(s.positions[v] - center)), 0.999f);
    for (uint32_t t = 0; t < s.triangle_count(); ++t) {
      if (s.triangle_material[t] != static_cast<uint32_t>(m)) continue;
      const auto v = s.vertices(t);
      ASSERT_GT(glm::dot(geometric_normal(s, t), (v[0] + v[1] + v[2]) / 3.0f - center), 0.0f) << "triangle " << t;
    }
  }
}

TEST(BuiltinSceneTest, WallsFaceInward) {
  const Scene s = make_builtin_scene("cornell");
  // Every wall triangle lies on a room face with its geometric normal pointing into the room.
  int wall_triangles = 0;
  for (uint32_t t = 0; t < s.triangle_count(); ++t) {
    const std::string& name = s.materials[s.triangle_material[t]].name;
    if (name != "white" && name != "red" && name != "green") continue;
    const auto v = s.vertices(t);
    for (int a = 0; a < 3; ++a)
      for (float side : {0.0f, 1.0f}) {
        if (v[0][a] != side || v[1][a] != side || v[2][a] != side) continue;
        ++wall_triangles;
        const float inward = side == 0.0f ? 1.0f : -1.0f;
        EXPECT_GT(geometric_normal(s, t)[a] * inward, 0.0f) << "triangle " << t;
        EXPECT_EQ(s.normals[s.triangles[t][0]][a], inward);
      }
  }
  EXPECT_EQ(wall_triangles, 5 * 128);
}

TEST(BuiltinSceneTest, UnknownNameIsInputError) {
  try {
    make_builtin_scene("x");
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "unknown builtin scene 'x' (known: cornell)");
  }
}

}  // namespace
}  // namespace rtusim
