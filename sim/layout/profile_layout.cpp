// Profile-guided layout: visit counts of a training frame into the greedy block packer.
#include "layout/profile_layout.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "layout/tree_measures.h"

namespace rtusim {

CameraDesc ProfileLayout::training_camera(const CameraDesc& camera, const Bounds3f& scene_box) {
  // The pivot: on the view axis, at the target or, when the scene box's centre is nearer
  // ahead (a small scene seen from afar), at the centre's depth, so the turned camera still
  // looks at the scene.
  const glm::vec3 f = glm::normalize(camera.target - camera.eye);
  const glm::vec3 centre = 0.5f * (glm::vec3(scene_box.min[0], scene_box.min[1], scene_box.min[2]) +
                                   glm::vec3(scene_box.max[0], scene_box.max[1], scene_box.max[2]));
  const float ahead = glm::dot(centre - camera.eye, f);
  const float target_ahead = glm::length(camera.target - camera.eye);
  const glm::vec3 pivot = camera.eye + (ahead > 0.0f ? std::min(ahead, target_ahead) : target_ahead) * f;
  // Rodrigues' rotation of the eye and the target about the pivot, around the up axis.
  const glm::vec3 k = glm::normalize(camera.up);
  const float a = glm::radians(kTrainingTurnDeg);
  const auto turn = [&](const glm::vec3& p) {
    const glm::vec3 v = p - pivot;
    return pivot + v * std::cos(a) + glm::cross(k, v) * std::sin(a) +
           k * glm::dot(k, v) * (1.0f - std::cos(a));
  };
  CameraDesc c = camera;
  c.eye = turn(camera.eye);
  c.target = turn(camera.target);
  c.name = camera.name + " (training)";
  return c;
}

MemoryImage ProfileLayout::build_image(const KdTree& tree, const Scene& scene) const {
  std::vector<double> priority = node_area_probabilities(tree);
  for (uint32_t i = 0; i < priority.size() && i < visits_.size(); ++i)
    priority[i] += double(visits_[i]);
  uint64_t slots = 0;
  const std::vector<uint32_t> slot_of = BlockCluster::pack(tree, priority, slots);
  return BlockCluster::write(tree, scene, kName, slot_of, slots);
}

}  // namespace rtusim
