// Built-in procedural scenes: deterministic geometry generated in code, no external file.
#include "scene/builtin_scene.h"

#include <cmath>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "util/error.h"

namespace rtusim {
namespace {

// Appends geometry to a scene, one material per call.
class MeshBuilder {
 public:
  explicit MeshBuilder(Scene& scene) : scene_(scene) {}

  uint32_t material(const Material& m) {
    scene_.materials.push_back(m);
    return static_cast<uint32_t>(scene_.materials.size() - 1);
  }

  uint32_t vertex(const glm::vec3& p, const glm::vec3& n) {
    scene_.positions.push_back(p);
    scene_.normals.push_back(n);
    return static_cast<uint32_t>(scene_.positions.size() - 1);
  }

  void triangle(uint32_t a, uint32_t b, uint32_t c, uint32_t material) {
    scene_.triangles.push_back({a, b, c});
    scene_.triangle_material.push_back(material);
  }

  // A flat quad origin + s*u + t*v (s, t in [0,1]) split into an n x n grid; the winding is
  // chosen so the geometric normal is cross(u, v).
  void grid_quad(const glm::vec3& origin, const glm::vec3& u, const glm::vec3& v, int n,
                 uint32_t material) {
    const glm::vec3 normal = glm::normalize(glm::cross(u, v));
    const uint32_t first = static_cast<uint32_t>(scene_.positions.size());
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        vertex(origin + u * (static_cast<float>(i) / n) + v * (static_cast<float>(j) / n), normal);
    auto at = [&](int i, int j) { return first + static_cast<uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        triangle(at(i, j), at(i + 1, j), at(i + 1, j + 1), material);
        triangle(at(i, j), at(i + 1, j + 1), at(i, j + 1), material);
      }
  }

  // A closed UV sphere: shared poles, shared seam, outward winding, exact sphere normals.
  void uv_sphere(const glm::vec3& center, float radius, int segments, int rings, uint32_t material) {
    const float pi = std::numbers::pi_v<float>;
    auto point = [&](float theta, float phi) {
      return glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                       -std::sin(theta) * std::sin(phi));
    };
    const uint32_t top = vertex(center + glm::vec3(0, radius, 0), glm::vec3(0, 1, 0));
    const uint32_t first_ring = static_cast<uint32_t>(scene_.positions.size());
    for (int r = 1; r < rings; ++r)
      for (int s = 0; s < segments; ++s) {
        const glm::vec3 d = point(pi * r / rings, 2.0f * pi * s / segments);
        vertex(center + radius * d, d);
      }
    const uint32_t bottom = vertex(center - glm::vec3(0, radius, 0), glm::vec3(0, -1, 0));
    auto at = [&](int r, int s) {
      return first_ring + static_cast<uint32_t>((r - 1) * segments + (s % segments));
    };
    // phi grows counter-clockwise seen from +Y, so (top, s, s+1) faces outward.
    for (int s = 0; s < segments; ++s) triangle(top, at(1, s), at(1, s + 1), material);
    for (int r = 1; r < rings - 1; ++r)
      for (int s = 0; s < segments; ++s) {
        triangle(at(r, s), at(r + 1, s), at(r + 1, s + 1), material);
        triangle(at(r, s), at(r + 1, s + 1), at(r, s + 1), material);
      }
    for (int s = 0; s < segments; ++s)
      triangle(bottom, at(rings - 1, s + 1), at(rings - 1, s), material);
  }

  // A closed icosphere (icosahedron subdivided `levels` times), outward winding.
  void icosphere(const glm::vec3& center, float radius, int levels, uint32_t material) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<glm::vec3> dirs = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                   {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                   {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (auto& d : dirs) d = glm::normalize(d);
    std::vector<std::array<uint32_t, 3>> faces = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int l = 0; l < levels; ++l) {
      std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
      auto mid = [&](uint32_t a, uint32_t b) {
        const auto key = std::minmax(a, b);
        auto it = midpoints.find(key);
        if (it != midpoints.end()) return it->second;
        dirs.push_back(glm::normalize(dirs[a] + dirs[b]));
        const uint32_t m = static_cast<uint32_t>(dirs.size() - 1);
        midpoints.emplace(key, m);
        return m;
      };
      std::vector<std::array<uint32_t, 3>> next;
      next.reserve(faces.size() * 4);
      for (const auto& f : faces) {
        const uint32_t ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
        next.push_back({f[0], ab, ca});
        next.push_back({f[1], bc, ab});
        next.push_back({f[2], ca, bc});
        next.push_back({ab, bc, ca});
      }
      faces = std::move(next);
    }
    const uint32_t first = static_cast<uint32_t>(scene_.positions.size());
    for (const auto& d : dirs) vertex(center + radius * d, d);
    for (const auto& f : faces) triangle(first + f[0], first + f[1], first + f[2], material);
  }

  // An axis-aligned closed box with outward winding and flat per-face normals.
  void box(const glm::vec3& lo, const glm::vec3& hi, uint32_t material) {
    const glm::vec3 d = hi - lo;
    const glm::vec3 x(d.x, 0, 0), y(0, d.y, 0), z(0, 0, d.z);
    grid_quad(lo, z, y, 1, material);                // -X
    grid_quad(lo + x, y, z, 1, material);            // +X
    grid_quad(lo, x, z, 1, material);                // -Y
    grid_quad(lo + y, z, x, 1, material);            // +Y
    grid_quad(lo, y, x, 1, material);                // -Z
    grid_quad(lo + z, x, y, 1, material);            // +Z
  }

 private:
  Scene& scene_;
};

Material diffuse(const std::string& name, const glm::vec3& color) {
  Material m;
  m.name = name;
  m.base_color = color;
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  return m;
}

// The Cornell-style room: [0,1]^3 open towards +Z, a mirror sphere, a glass sphere, a block,
// an emissive ceiling quad, one point light and the "default" camera.
Scene make_cornell() {
  Scene scene;
  scene.source = "builtin:cornell";
  MeshBuilder mb(scene);
  const uint32_t white = mb.material(diffuse("white", {0.73f, 0.73f, 0.73f}));
  const uint32_t red = mb.material(diffuse("red", {0.63f, 0.065f, 0.05f}));
  const uint32_t green = mb.material(diffuse("green", {0.14f, 0.45f, 0.09f}));
  Material mirror_mat;
  mirror_mat.name = "mirror";
  mirror_mat.base_color = glm::vec3(0.95f);
  mirror_mat.metallic = 1.0f;
  mirror_mat.roughness = 0.0f;
  const uint32_t mirror = mb.material(mirror_mat);
  Material glass_mat;
  glass_mat.name = "glass";
  glass_mat.metallic = 0.0f;
  glass_mat.roughness = 0.0f;
  glass_mat.transmission = 1.0f;
  glass_mat.ior = 1.5f;
  const uint32_t glass = mb.material(glass_mat);
  const uint32_t block = mb.material(diffuse("block", {0.73f, 0.73f, 0.73f}));
  Material light_mat = diffuse("light", {1.0f, 1.0f, 1.0f});
  light_mat.emissive = glm::vec3(1.0f);
  const uint32_t light = mb.material(light_mat);

  // Walls, 8 x 8 grids with inward normals (cross(u, v) points into the room).
  const int n = 8;
  const glm::vec3 X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
  mb.grid_quad({0, 0, 0}, Z, X, n, white);  // floor, normal +Y
  mb.grid_quad({0, 1, 0}, X, Z, n, white);  // ceiling, normal -Y
  mb.grid_quad({0, 0, 0}, X, Y, n, white);  // back wall, normal +Z
  mb.grid_quad({0, 0, 0}, Y, Z, n, red);    // left wall, normal +X
  mb.grid_quad({1, 0, 0}, Z, Y, n, green);  // right wall, normal -X

  // Objects: mirror sphere (UV, 1472 triangles), glass icosphere (1280), diffuse block (12).
  mb.uv_sphere({0.3f, 0.21f, 0.35f}, 0.2f, 32, 24, mirror);
  mb.icosphere({0.68f, 0.18f, 0.68f}, 0.17f, 3, glass);
  mb.box({0.62f, 0.0f, 0.12f}, {0.86f, 0.35f, 0.36f}, block);

  // Emissive quad just under the ceiling, facing down.
  mb.grid_quad({0.4f, 0.999f, 0.4f}, X * 0.2f, Z * 0.2f, 1, light);

  PointLight point;
  point.name = "ceiling";
  point.position = glm::vec3(0.5f, 0.95f, 0.5f);
  scene.lights.push_back(point);

  CameraDesc cam;
  cam.name = "default";
  cam.eye = glm::vec3(0.5f, 0.5f, 2.0f);
  cam.target = glm::vec3(0.5f, 0.5f, 0.0f);
  cam.up = glm::vec3(0.0f, 1.0f, 0.0f);
  cam.vfov_deg = 40.0f;
  scene.cameras.push_back(cam);
  return scene;
}

}  // namespace

Scene make_builtin_scene(const std::string& name) {
  if (name == "cornell") return make_cornell();
  throw InputError("unknown builtin scene '" + name + "' (known: cornell)");
}

}  // namespace rtusim
