// Profile-guided layout: the block-cluster layout (layout/block_cluster.h) with the greedy
// packer driven by measured visit counts instead of surface areas. The counts come from a
// training frame that is not the frame measured: the run's camera turned by kTrainingTurnDeg
// about the camera's up axis, around its target or, when the scene box's centre lies nearer
// ahead, around the point of the view axis at the centre's depth; kTrainingSize x kTrainingSize
// pixels, the run's tracer settings, traced over a DFL image of the same tree. The view
// direction turns by kTrainingTurnDeg and the eye moves 2 sin(kTrainingTurnDeg / 2) times the
// pivot distance (0.35 units for a glTF camera, whose target is 1 unit ahead).
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "layout/block_cluster.h"
#include "layout/layout.h"
#include "layout/node_view.h"
#include "scene/scene.h"

namespace rtusim {

// Encoding: layout/block_cluster.h (8-byte nodes, 3-bit in-block child slots, global slots for
// children outside the block); no node straddles a 64-byte block.
// Placement: BlockCluster::pack with priority of node i = its visit count in the training
// frame plus its surface-area probability (< 1, so it only orders nodes of equal count, e.g.
// the ones the training frame never reached). Deterministic for given counts.
// The decoder, decode(image, addr), is BlockCluster's.
class ProfileLayout final : public Layout, public BlockCluster {
 public:
  static constexpr float kTrainingTurnDeg = 20.0f;
  static constexpr int kTrainingSize = 128;

  ProfileLayout() = default;
  // Visit counts per logical node (empty: none measured, surface areas alone decide).
  explicit ProfileLayout(std::vector<uint64_t> visits) : visits_(std::move(visits)) {}

  static constexpr const char* kName = "profile";
  std::string_view name() const override { return kName; }
  MemoryImage build_image(const KdTree& tree, const Scene& scene) const override;

  // The visit counts of the training frame (measured by app/profile_training.h).
  void set_visits(std::vector<uint64_t> visits) { visits_ = std::move(visits); }
  const std::vector<uint64_t>& visits() const { return visits_; }

  // The training camera: `camera` turned by kTrainingTurnDeg around its target, or around the
  // point of its view axis level with the centre of `scene_box` if that is nearer ahead.
  static CameraDesc training_camera(const CameraDesc& camera, const Bounds3f& scene_box);

 private:
  std::vector<uint64_t> visits_;
};

}  // namespace rtusim
