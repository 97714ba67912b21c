// glTF 2.0 loading: tinygltf parses the file, this file flattens the default scene into
// world-space triangles in the contract's load order and checks every range it reads.
#include "scene/gltf_loader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <tiny_gltf.h>

#include "util/error.h"
#include "util/read_text_file.h"

namespace rtusim {
namespace {

// The largest |coordinate| of a vertex (see the check where positions are read).
constexpr double kMaxCoordinate = 1e18;

// Image callback that keeps images undecoded: the simulator never reads textures.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
  return true;
}

// Collapses multi-line text (tinygltf's messages) into one line.
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ';';
  while (!text.empty() && (text.back() == ';' || text.back() == ' ')) text.pop_back();
  return text;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// A number from a tinygltf Value, or the fallback when absent or not numeric.
double number_or(const tinygltf::Value& v, const char* key, double fallback) {
  if (!v.IsObject() || !v.Has(key)) return fallback;
  const tinygltf::Value& n = v.Get(key);
  return n.IsNumber() ? n.GetNumberAsDouble() : fallback;
}

// A bounds-checked, strided view of one accessor's elements.
struct AccessorView {
  const unsigned char* base = nullptr;
  size_t stride = 0;
  size_t count = 0;
  int component_type = 0;
  int components = 0;
  bool normalized = false;

  const unsigned char* element(size_t i) const { return base + i * stride; }
};

// Reads component c of element i as a double (normalized integers mapped per the glTF spec).
double read_component(const AccessorView& a, size_t i, int c) {
  const unsigned char* p = a.element(i);
  switch (a.component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p + 4 * c, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p + c, 1);
      return a.normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      uint8_t v;
      std::memcpy(&v, p + c, 1);
      return a.normalized ? v / 255.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p + 2 * c, 2);
      return a.normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p + 2 * c, 2);
      return a.normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p + 4 * c, 4);
      return a.normalized ? v / 4294967295.0 : v;
    }
    default:
      return 0.0;
  }
}

// Reads index i of an unsigned-integer SCALAR accessor.
uint32_t read_index(const AccessorView& a, size_t i) {
  const unsigned char* p = a.element(i);
  switch (a.component_type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return *p;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    default: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

glm::vec3 read_vec3(const AccessorView& a, size_t i) {
  if (a.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT) {
    float f[3];
    std::memcpy(f, a.element(i), sizeof(f));
    return {f[0], f[1], f[2]};
  }
  return {read_component(a, i, 0), read_component(a, i, 1), read_component(a, i, 2)};
}

// The deepest JSON nesting of `text` (arrays and objects), strings skipped; stops counting
// once `limit` is passed.
int json_depth(std::string_view text, int limit) {
  int depth = 0, deepest = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
      if (deepest > limit) break;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

uint32_t le_u32(const unsigned char* p) {
  return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
}

// What tinygltf would trip over, checked first on the file's bytes: a .glb's header and version,
// and JSON nested so deep that the recursive JSON parser would overflow the stack.
void check_json_before_parse(const std::string& path, std::string_view file, bool glb,
                             const SceneLimits& limits) {
  std::string_view json = file;
  if (glb) {
    const auto* head = reinterpret_cast<const unsigned char*>(file.data());
    if (file.size() < 20) throw InputError(path + ": truncated .glb (" + std::to_string(file.size()) +
                                           " bytes, shorter than its 20-byte header)");
    if (std::memcmp(head, "glTF", 4) != 0) throw InputError(path + ": not a .glb (bad magic)");
    if (le_u32(head + 4) != 2)
      throw InputError(path + ": unsupported .glb version " + std::to_string(le_u32(head + 4)) +
                       " (need 2)");
    const uint32_t json_bytes = le_u32(head + 12);
    if (le_u32(head + 16) != 0x4E4F534Au)
      throw InputError(path + ": .glb's first chunk is not JSON");
    json = file.substr(20, json_bytes);
  }
  if (json_depth(json, limits.max_json_depth) > limits.max_json_depth)
    throw InputError(path + ": JSON nested deeper than " + std::to_string(limits.max_json_depth) +
                     " levels");
}

// A node instance reached by the traversal, with its world transform.
struct NodeInstance {
  int node = -1;
  glm::dmat4 world{1.0};
};

class GltfFlattener {
 public:
  GltfFlattener(const std::string& path, const tinygltf::Model& model, const SceneLimits& limits)
      : path_(path), model_(model), limits_(limits) {}

  Scene run() {
    Scene scene;
    scene.source = path_;
    check_asset_version();
    check_required_extensions();
    collect_instances();
    copy_materials(scene);
    reserve(scene);
    for (const NodeInstance& inst : instances_) {
      const tinygltf::Node& node = model_.nodes[static_cast<size_t>(inst.node)];
      if (node.mesh >= 0) add_mesh(scene, inst, node.mesh);
      add_light(scene, inst, node);
      add_camera(scene, inst, node);
    }
    if (scene.triangles.empty()) fail("no triangles in the default scene");
    add_suggested_light(scene);
    return scene;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_ + ": " + what);
  }

  // Local transform of a node: its matrix if present, else T * R * S.
  glm::dmat4 local_transform(const tinygltf::Node& node, int index) const {
    const std::string ctx = "node " + std::to_string(index) + ": ";
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16) fail(ctx + "matrix needs 16 numbers");
      return checked_transform(glm::make_mat4(node.matrix.data()), ctx);
    }
    glm::dmat4 m(1.0);
    if (!node.translation.empty()) {
      if (node.translation.size() != 3) fail(ctx + "translation needs 3 numbers");
      m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
    }
    if (!node.rotation.empty()) {
      if (node.rotation.size() != 4) fail(ctx + "rotation needs 4 numbers");
      glm::dquat q;
      q.x = node.rotation[0];
      q.y = node.rotation[1];
      q.z = node.rotation[2];
      q.w = node.rotation[3];
      m = m * glm::mat4_cast(glm::normalize(q));
    }
    if (!node.scale.empty()) {
      if (node.scale.size() != 3) fail(ctx + "scale needs 3 numbers");
      m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    }
    return checked_transform(m, ctx);
  }

  // A transform must be finite and invertible (a scale of 0 flattens the geometry).
  glm::dmat4 checked_transform(const glm::dmat4& m, const std::string& ctx) const {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(m[c][r])) fail(ctx + "transform holds a non-finite number");
    const double det = glm::determinant(glm::dmat3(m));
    if (!(std::abs(det) > 0.0)) fail(ctx + "transform is singular (a scale of 0?)");
    return m;
  }

  // Root nodes of the default scene (defaultScene, else scene 0, else every parentless node).
  std::vector<int> root_nodes() const {
    const int node_count = static_cast<int>(model_.nodes.size());
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      const int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
      if (s >= static_cast<int>(model_.scenes.size()))
        fail("default scene " + std::to_string(s) + " out of range (" +
             std::to_string(model_.scenes.size()) + " scenes)");
      roots = model_.scenes[static_cast<size_t>(s)].nodes;
      for (int n : roots)
        if (n < 0 || n >= node_count)
          fail("scene " + std::to_string(s) + ": node " + std::to_string(n) + " out of range (" +
               std::to_string(node_count) + " nodes)");
      return roots;
    }
    std::vector<bool> is_child(model_.nodes.size(), false);
    for (int i = 0; i < node_count; ++i)
      for (int c : model_.nodes[static_cast<size_t>(i)].children)
        if (c >= 0 && c < node_count) is_child[static_cast<size_t>(c)] = true;
    for (int i = 0; i < node_count; ++i)
      if (!is_child[static_cast<size_t>(i)]) roots.push_back(i);
    return roots;
  }

  // Depth-first traversal, children in order; world = parent * local. An explicit stack, so a
  // deep hierarchy cannot overflow the call stack; instances are capped (kMaxInstances).
  void collect_instances() {
    const int node_count = static_cast<int>(model_.nodes.size());
    std::vector<bool> on_path(model_.nodes.size(), false);
    struct Frame {
      int node;
      size_t next_child;
      glm::dmat4 world;
    };
    std::vector<Frame> stack;
    auto enter = [&](int n, const glm::dmat4& parent) {
      if (on_path[static_cast<size_t>(n)]) fail("node " + std::to_string(n) + " is its own ancestor");
      const tinygltf::Node& node = model_.nodes[static_cast<size_t>(n)];
      const glm::dmat4 local = local_transform(node, n);
      const glm::dmat4 world = parent * local;
      if (instances_.size() >= kMaxInstances)
        fail("more than " + std::to_string(kMaxInstances) + " node instances in the default scene");
      instances_.push_back({n, world});
      on_path[static_cast<size_t>(n)] = true;
      stack.push_back({n, 0, world});
    };
    for (int r : root_nodes()) {
      enter(r, glm::dmat4(1.0));
      while (!stack.empty()) {
        Frame& f = stack.back();
        const tinygltf::Node& node = model_.nodes[static_cast<size_t>(f.node)];
        if (f.next_child == node.children.size()) {
          on_path[static_cast<size_t>(f.node)] = false;
          stack.pop_back();
          continue;
        }
        const int c = node.children[f.next_child++];
        if (c < 0 || c >= node_count)
          fail("node " + std::to_string(f.node) + ": child " + std::to_string(c) +
               " out of range (" + std::to_string(node_count) + " nodes)");
        const glm::dmat4 world = f.world;  // `f` dangles once enter() grows the stack
        enter(c, world);
      }
    }
  }

  // glTF 2.x only (a 1.0 file is another format whose meshes would be misread).
  void check_asset_version() const {
    const std::string& v = model_.asset.version;
    if (v.empty() || v.substr(0, v.find('.')) != "2")
      fail("asset.version '" + v + "': only glTF 2.x is read");
  }

  // A file that requires an extension this loader does not read cannot be read right (the
  // glTF spec: such a file must be refused). Extensions that only change textures or shading
  // terms the tracer does not model are read by ignoring them.
  void check_required_extensions() const {
    static const std::set<std::string> understood = {
        "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_ior",
        "KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_specular",
        "KHR_materials_clearcoat", "KHR_materials_sheen", "KHR_materials_iridescence",
        "KHR_materials_unlit", "KHR_texture_transform", "KHR_texture_basisu", "EXT_texture_webp"};
    for (const std::string& ext : model_.extensionsRequired)
      if (!understood.count(ext)) fail("requires extension " + ext + ", which rtusim does not read");
  }

  // A material factor outside the glTF spec's range would make the tracer add energy (an ior
  // below 1 gives a Fresnel reflectance above 1): refused, naming the material.
  void check_factor(size_t index, const tinygltf::Material& m, const char* what, double value,
                    double low, double high) const {
    if (!(value >= low && value <= high))
      fail("material " + std::to_string(index) + (m.name.empty() ? "" : " '" + m.name + "'") +
           ": " + what + " " + format_number(value) + " is not in [" + format_number(low) +
           ", " + format_number(high) + "]");
  }
  static std::string format_number(double v) {  // as written: 1.5, 5, -0.5, inf
    std::ostringstream os;
    os << v;
    return os.str();
  }

  // Materials keep their glTF indices; the glTF default material is appended on demand.
  void copy_materials(Scene& scene) const {
    scene.materials.reserve(model_.materials.size() + 1);
    for (const tinygltf::Material& m : model_.materials) {
      Material out;
      out.name = m.name;
      const auto& pbr = m.pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() >= 3)
        out.base_color =
            glm::vec3(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2]);
      out.metallic = static_cast<float>(pbr.metallicFactor);
      out.roughness = static_cast<float>(pbr.roughnessFactor);
      if (m.emissiveFactor.size() == 3)
        out.emissive = glm::vec3(m.emissiveFactor[0], m.emissiveFactor[1], m.emissiveFactor[2]);
      if (auto it = m.extensions.find("KHR_materials_emissive_strength"); it != m.extensions.end())
        out.emissive *= static_cast<float>(number_or(it->second, "emissiveStrength", 1.0));
      if (auto it = m.extensions.find("KHR_materials_transmission"); it != m.extensions.end())
        out.transmission = static_cast<float>(number_or(it->second, "transmissionFactor", 0.0));
      if (auto it = m.extensions.find("KHR_materials_ior"); it != m.extensions.end())
        out.ior = static_cast<float>(number_or(it->second, "ior", 1.5));
      const size_t i = scene.materials.size();
      const double inf = std::numeric_limits<double>::infinity();
      for (size_t c = 0; c < pbr.baseColorFactor.size(); ++c)
        check_factor(i, m, "baseColorFactor", pbr.baseColorFactor[c], 0.0, 1.0);
      check_factor(i, m, "metallicFactor", pbr.metallicFactor, 0.0, 1.0);
      check_factor(i, m, "roughnessFactor", pbr.roughnessFactor, 0.0, 1.0);
      for (const double e : m.emissiveFactor) check_factor(i, m, "emissiveFactor", e, 0.0, 1.0);
      if (auto it = m.extensions.find("KHR_materials_emissive_strength"); it != m.extensions.end())
        check_factor(i, m, "emissiveStrength", number_or(it->second, "emissiveStrength", 1.0), 0.0, inf);
      check_factor(i, m, "transmissionFactor", out.transmission, 0.0, 1.0);
      check_factor(i, m, "ior", out.ior, 1.0, inf);
      scene.materials.push_back(out);
    }
  }

  uint32_t default_material(Scene& scene) {
    if (default_material_ < 0) {
      default_material_ = static_cast<int>(scene.materials.size());
      Material m;
      m.name = "gltf_default";
      scene.materials.push_back(m);
    }
    return static_cast<uint32_t>(default_material_);
  }

  // Checks an accessor against its buffer view and buffer and returns a view of its elements.
  AccessorView view_of(int accessor_index, const std::string& what) const {
    const std::string ctx = "accessor " + std::to_string(accessor_index) + " (" + what + ")";
    if (accessor_index < 0 || accessor_index >= static_cast<int>(model_.accessors.size()))
      fail(ctx + ": out of range (" + std::to_string(model_.accessors.size()) + " accessors)");
    const tinygltf::Accessor& acc = model_.accessors[static_cast<size_t>(accessor_index)];
    if (acc.sparse.isSparse) fail(ctx + ": sparse accessors are not supported");
    AccessorView v;
    v.count = acc.count;
    v.component_type = acc.componentType;
    v.components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(acc.type));
    v.normalized = acc.normalized;
    const int comp_bytes = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(acc.componentType));
    if (v.components <= 0 || comp_bytes <= 0) fail(ctx + ": unknown type or componentType");
    if (acc.count == 0) return v;
    if (acc.bufferView < 0 || acc.bufferView >= static_cast<int>(model_.bufferViews.size()))
      fail(ctx + ": buffer view " + std::to_string(acc.bufferView) + " out of range (" +
           std::to_string(model_.bufferViews.size()) + " buffer views)");
    const tinygltf::BufferView& bv = model_.bufferViews[static_cast<size_t>(acc.bufferView)];
    const std::string bv_ctx = "buffer view " + std::to_string(acc.bufferView);
    if (bv.buffer < 0 || bv.buffer >= static_cast<int>(model_.buffers.size()))
      fail(bv_ctx + ": buffer " + std::to_string(bv.buffer) + " out of range (" +
           std::to_string(model_.buffers.size()) + " buffers)");
    const tinygltf::Buffer& buf = model_.buffers[static_cast<size_t>(bv.buffer)];
    if (bv.byteOffset > buf.data.size() || bv.byteLength > buf.data.size() - bv.byteOffset)
      fail(bv_ctx + ": bytes " + std::to_string(bv.byteOffset) + ".." +
           std::to_string(bv.byteOffset + bv.byteLength) + " out of range (buffer " +
           std::to_string(bv.buffer) + " has " + std::to_string(buf.data.size()) + " bytes)");
    const size_t elem_bytes = static_cast<size_t>(comp_bytes) * static_cast<size_t>(v.components);
    v.stride = bv.byteStride != 0 ? bv.byteStride : elem_bytes;
    if (v.stride < elem_bytes)
      fail(ctx + ": byteStride " + std::to_string(v.stride) + " smaller than the element (" +
           std::to_string(elem_bytes) + " bytes)");
    const size_t max_count = std::numeric_limits<size_t>::max() / v.stride;
    const bool too_long = acc.count - 1 > max_count || acc.byteOffset > bv.byteLength ||
                          (acc.count - 1) * v.stride + elem_bytes > bv.byteLength - acc.byteOffset;
    if (too_long)
      fail(ctx + ": " + std::to_string(acc.count) + " elements from byte " +
           std::to_string(acc.byteOffset) + " overrun " + bv_ctx + " (" +
           std::to_string(bv.byteLength) + " bytes)");
    v.base = buf.data.data() + bv.byteOffset + acc.byteOffset;
    return v;
  }

  // Reserves vertex and triangle storage from the accessor counts of every instanced primitive.
  void reserve(Scene& scene) const {
    size_t vertices = 0;
    size_t triangles = 0;
    for (const NodeInstance& inst : instances_) {
      const int mesh = model_.nodes[static_cast<size_t>(inst.node)].mesh;
      if (mesh < 0 || mesh >= static_cast<int>(model_.meshes.size())) continue;
      for (const tinygltf::Primitive& p : model_.meshes[static_cast<size_t>(mesh)].primitives) {
        auto pos = p.attributes.find("POSITION");
        if (pos == p.attributes.end() || pos->second < 0 ||
            pos->second >= static_cast<int>(model_.accessors.size()))
          continue;
        // Counts are checked against their buffers before anything is allocated from them.
        size_t n = view_of(pos->second, "POSITION").count;
        vertices += n;
        if (p.indices >= 0) n = view_of(p.indices, "indices").count;
        if (p.mode == TINYGLTF_MODE_TRIANGLES || p.mode == -1) triangles += n / 3;
        else if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP || p.mode == TINYGLTF_MODE_TRIANGLE_FAN)
          triangles += n >= 3 ? n - 2 : 0;
      }
    }
    const uint64_t bytes = uint64_t{vertices} * 2 * sizeof(glm::vec3) +
                           uint64_t{triangles} * (sizeof(scene.triangles[0]) + sizeof(uint32_t));
    if (bytes > limits_.max_scene_bytes)
      fail("the scene needs " + std::to_string(bytes >> 20) + " MiB of geometry, over the limit of " +
           std::to_string(limits_.max_scene_bytes >> 20) + " MiB (RTUSIM_MAX_SCENE_MB)");
    scene.positions.reserve(vertices);
    scene.normals.reserve(vertices);
    scene.triangles.reserve(triangles);
    scene.triangle_material.reserve(triangles);
  }

  void add_mesh(Scene& scene, const NodeInstance& inst, int mesh_index) {
    if (mesh_index >= static_cast<int>(model_.meshes.size()))
      fail("node " + std::to_string(inst.node) + ": mesh " + std::to_string(mesh_index) +
           " out of range (" + std::to_string(model_.meshes.size()) + " meshes)");
    const tinygltf::Mesh& mesh = model_.meshes[static_cast<size_t>(mesh_index)];
    const glm::dmat3 linear(inst.world);
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
    // A mirroring transform reverses the winding; swapping two indices keeps normals outward.
    const bool flip = glm::determinant(linear) < 0.0;
    for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
      const tinygltf::Primitive& prim = mesh.primitives[pi];
      const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
      if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
          mode != TINYGLTF_MODE_TRIANGLE_FAN)
        continue;
      const std::string where = "of mesh '" + mesh.name + "' (" + std::to_string(mesh_index) +
                                ") primitive " + std::to_string(pi);
      add_primitive(scene, inst, prim, mode, where, normal_matrix, flip);
    }
  }

  void add_primitive(Scene& scene, const NodeInstance& inst, const tinygltf::Primitive& prim,
                     int mode, const std::string& where, const glm::dmat3& normal_matrix, bool flip) {
    auto pos_it = prim.attributes.find("POSITION");
    if (pos_it == prim.attributes.end()) fail("primitive " + where + ": no POSITION attribute");
    const AccessorView pos = view_of(pos_it->second, "POSITION " + where);
    if (pos.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT || pos.components != 3)
      fail("accessor " + std::to_string(pos_it->second) + " (POSITION " + where +
           "): non-float positions (need float VEC3)");
    AccessorView nrm;
    bool has_normals = false;
    if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
      nrm = view_of(it->second, "NORMAL " + where);
      if (nrm.components != 3)
        fail("accessor " + std::to_string(it->second) + " (NORMAL " + where + "): not VEC3");
      if (nrm.count != pos.count)
        fail("accessor " + std::to_string(it->second) + " (NORMAL " + where + "): " +
             std::to_string(nrm.count) + " normals for " + std::to_string(pos.count) + " positions");
      has_normals = true;
    }
    uint32_t material = 0;
    if (prim.material < 0) {
      material = default_material(scene);
    } else if (prim.material >= static_cast<int>(model_.materials.size())) {
      fail("primitive " + where + ": material " + std::to_string(prim.material) + " out of range (" +
           std::to_string(model_.materials.size()) + " materials)");
    } else {
      material = static_cast<uint32_t>(prim.material);
    }

    // Vertices, transformed to world space.
    const size_t base = scene.positions.size();
    if (base + pos.count > std::numeric_limits<uint32_t>::max()) fail("more than 2^32 vertices");
    const bool identity = inst.world == glm::dmat4(1.0);
    for (size_t i = 0; i < pos.count; ++i) {
      const glm::vec3 p = read_vec3(pos, i);
      const glm::vec3 w = identity ? p : glm::vec3(inst.world * glm::dvec4(p, 1.0));
      // Finite, and not beyond kMaxCoordinate, where the ray/triangle test's float products
      // overflow (the camera's own limit is ~1e19): refused rather than rays missing triangles.
      const bool finite = std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z);
      if (!finite || std::max({std::abs(w.x), std::abs(w.y), std::abs(w.z)}) > kMaxCoordinate)
        fail("accessor " + std::to_string(pos_it->second) + " (POSITION " + where + "): element " +
             std::to_string(i) +
             (finite ? " lies beyond +-1e18, too far out for single precision"
                     : " is not a finite position"));
      scene.positions.push_back(w);
      if (!has_normals) {
        scene.normals.emplace_back(0.0f);
        continue;
      }
      glm::dvec3 n = glm::dvec3(read_vec3(nrm, i));
      if (!identity) n = normal_matrix * n;
      const double len = glm::length(n);
      scene.normals.push_back(len > 0.0 ? glm::vec3(n / len) : glm::vec3(0.0f));
    }

    // Index list: the index accessor, or 0..count-1 when the primitive is not indexed.
    AccessorView idx;
    std::string idx_ctx;
    size_t index_count = pos.count;
    if (prim.indices >= 0) {
      idx_ctx = "accessor " + std::to_string(prim.indices) + " (indices " + where + ")";
      idx = view_of(prim.indices, "indices " + where);
      const bool unsigned_int = idx.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                idx.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                                idx.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
      if (idx.components != 1 || !unsigned_int)
        fail(idx_ctx + ": indices must be unsigned integer SCALAR");
      index_count = idx.count;
    }
    auto vertex = [&](size_t k) -> uint32_t {
      if (prim.indices < 0) return static_cast<uint32_t>(base + k);
      const uint32_t v = read_index(idx, k);
      if (v >= pos.count)
        fail(idx_ctx + ": index " + std::to_string(v) + " out of range (" + std::to_string(pos.count) +
             " vertices)");
      return static_cast<uint32_t>(base + v);
    };
    auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
      if (flip) std::swap(b, c);
      scene.triangles.push_back({a, b, c});
      scene.triangle_material.push_back(material);
    };

    // Triangles in index order; strips and fans unrolled with the glTF spec's formulas.
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      for (size_t k = 0; k + 2 < index_count; k += 3) emit(vertex(k), vertex(k + 1), vertex(k + 2));
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (size_t k = 0; k + 2 < index_count; ++k)
        emit(vertex(k), vertex(k + 1 + k % 2), vertex(k + 2 - k % 2));
    } else {
      for (size_t k = 0; k + 2 < index_count; ++k) emit(vertex(k + 1), vertex(k + 2), vertex(0));
    }
  }

  // KHR_lights_punctual: point lights at the node's world origin; spot and directional skipped.
  void add_light(Scene& scene, const NodeInstance& inst, const tinygltf::Node& node) const {
    auto it = node.extensions.find("KHR_lights_punctual");
    if (it == node.extensions.end() || !it->second.IsObject() || !it->second.Has("light")) return;
    const tinygltf::Value& v = it->second.Get("light");
    const int li = v.IsNumber() ? static_cast<int>(v.GetNumberAsDouble()) : -1;
    if (li < 0 || li >= static_cast<int>(model_.lights.size()))
      fail("node " + std::to_string(inst.node) + ": light " + std::to_string(li) + " out of range (" +
           std::to_string(model_.lights.size()) + " lights)");
    const tinygltf::Light& light = model_.lights[static_cast<size_t>(li)];
    if (light.type != "point") return;
    PointLight out;
    out.name = !light.name.empty() ? light.name : node.name;
    out.position = glm::vec3(inst.world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
    if (light.color.size() == 3) out.color = glm::vec3(light.color[0], light.color[1], light.color[2]);
    out.intensity = static_cast<float>(light.intensity);
    scene.lights.push_back(out);
  }

  // Perspective camera nodes: eye at the node origin, looking down world -Z of the node.
  void add_camera(Scene& scene, const NodeInstance& inst, const tinygltf::Node& node) const {
    if (node.camera < 0) return;
    if (node.camera >= static_cast<int>(model_.cameras.size()))
      fail("node " + std::to_string(inst.node) + ": camera " + std::to_string(node.camera) +
           " out of range (" + std::to_string(model_.cameras.size()) + " cameras)");
    const tinygltf::Camera& cam = model_.cameras[static_cast<size_t>(node.camera)];
    if (cam.type != "perspective") return;
    const glm::dmat3 linear(inst.world);
    const glm::dvec3 eye(inst.world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
    const glm::dvec3 forward = glm::normalize(linear * glm::dvec3(0.0, 0.0, -1.0));
    const double yfov = cam.perspective.yfov;
    if (!(yfov > 0.0 && yfov < glm::pi<double>()))
      fail("camera " + std::to_string(node.camera) + ": yfov " + std::to_string(yfov) +
           " rad is not in (0, pi)");
    CameraDesc out;
    out.name = !node.name.empty() ? node.name
               : !cam.name.empty() ? cam.name
                                   : "camera" + std::to_string(inst.node);
    out.eye = glm::vec3(eye);
    // The target one unit ahead (the profile layout's training view turns about it), or, where
    // float rounding bends that step by over 1e-4 rad (a tenth of a pixel at 1024^2; an eye
    // some 4000 units or more from the origin: at 1e6 by ~1 degree, at 3e7 the target equals
    // the eye), as far ahead as the eye is from the origin.
    out.target = glm::vec3(eye + forward);
    const glm::dvec3 step = glm::dvec3(out.target) - glm::dvec3(out.eye);
    if (!(glm::length(step) > 0.0) || glm::dot(glm::normalize(step), forward) < std::cos(1e-4))
      out.target = glm::vec3(eye + forward * glm::length(eye));
    out.up = glm::vec3(glm::normalize(linear * glm::dvec3(0.0, 1.0, 0.0)));
    out.vfov_deg = static_cast<float>(glm::degrees(cam.perspective.yfov));
    scene.cameras.push_back(out);
  }

  // asset.extras.point_light_suggestion becomes a point light when the file has no lights. It
  // is either three numbers or an object {position: [x, y, z], color: [r, g, b]}.
  void add_suggested_light(Scene& scene) const {
    if (!scene.lights.empty()) return;
    const tinygltf::Value& extras = model_.asset.extras;
    if (!extras.IsObject() || !extras.Has("point_light_suggestion")) return;
    const tinygltf::Value& s = extras.Get("point_light_suggestion");
    glm::vec3 position;
    if (!vec3_of(s.IsObject() ? s.Get("position") : s, position)) return;
    PointLight light;
    light.name = "point_light_suggestion";
    light.position = position;
    if (s.IsObject()) vec3_of(s.Get("color"), light.color);
    scene.lights.push_back(light);
  }

  // Three numbers from a JSON array; false (out untouched) otherwise.
  static bool vec3_of(const tinygltf::Value& v, glm::vec3& out) {
    if (!v.IsArray() || v.ArrayLen() != 3) return false;
    for (int i = 0; i < 3; ++i)
      if (!v.Get(i).IsNumber()) return false;
    out = glm::vec3(v.Get(0).GetNumberAsDouble(), v.Get(1).GetNumberAsDouble(),
                    v.Get(2).GetNumberAsDouble());
    return true;
  }

  static constexpr size_t kMaxInstances = size_t{1} << 20;

  const std::string& path_;
  const tinygltf::Model& model_;
  const SceneLimits& limits_;
  std::vector<NodeInstance> instances_;
  int default_material_ = -1;
};

}  // namespace

SceneLimits SceneLimits::from_environment() {
  SceneLimits l;
  if (const char* mb = std::getenv("RTUSIM_MAX_SCENE_MB")) {
    char* end = nullptr;
    const unsigned long long v = std::strtoull(mb, &end, 10);
    if (end == mb || *end != '\0' || v == 0 || v > (uint64_t{1} << 40))
      throw InputError(std::string("RTUSIM_MAX_SCENE_MB: '") + mb + "' is not a size in MiB");
    l.max_scene_bytes = uint64_t{v} << 20;
  }
  return l;
}

Scene load_gltf(const std::string& path, const SceneLimits& limits) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path + ": is a directory (need a .gltf or .glb file)");
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  if (ext != ".gltf" && ext != ".glb")
    throw InputError(path + ": unknown scene file extension '" + ext + "' (need .gltf or .glb)");
  if (!std::filesystem::exists(path, ec)) throw InputError(path + ": file not found");
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path + ": not a regular file (need a .gltf or .glb file)");
  const uint64_t file_bytes = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path + ": cannot read the file");
  if (file_bytes > limits.max_scene_bytes)
    throw InputError(path + ": " + std::to_string(file_bytes >> 20) + " MiB file, over the limit of " +
                     std::to_string(limits.max_scene_bytes >> 20) + " MiB (RTUSIM_MAX_SCENE_MB)");
  // The file is read once: checked, then parsed from memory.
  const std::optional<std::string> read = read_text_file(path);
  if (!read) throw InputError(path + ": cannot read the file");
  const std::string& file = *read;
  const bool glb = ext == ".glb";
  check_json_before_parse(path, file, glb, limits);

  // Parse with tinygltf; images are left undecoded and a missing image is only a warning.
  // External buffers and images are found beside the file.
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&skip_image, nullptr);
  tinygltf::Model model;
  std::string err;
  std::string warn;
  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  const bool ok =
      glb ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                        reinterpret_cast<const unsigned char*>(file.data()),
                                        static_cast<unsigned>(file.size()), base_dir)
          : loader.LoadASCIIFromString(&model, &err, &warn, file.data(),
                                       static_cast<unsigned>(file.size()), base_dir);
  if (!ok)
    throw InputError(path + ": cannot parse glTF: " + one_line(err.empty() ? "unknown error" : err));

  return GltfFlattener(path, model, limits).run();
}

}  // namespace rtusim
