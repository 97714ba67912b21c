// The profile layout's training frame: a DFL traversal that counts visits per logical node.
#include "app/profile_training.h"

#include <span>
#include <utility>

#include "layout/dfl_layout.h"
#include "layout/profile_layout.h"
#include "scene/pinhole_camera.h"
#include "tracer/whitted_tracer.h"
#include "traversal/traversal.h"

namespace rtusim {
namespace {

// Traces batches over a DFL image and counts visits per logical node.
class VisitCounter final : public TraceBackend {
 public:
  VisitCounter(const KdTree& tree, const MemoryImage& image)
      : image_(image), node_at_slot_(tree.nodes.size()), visits_(tree.nodes.size(), 0) {
    // DFL slot -> logical node, walking the image beside the tree.
    std::vector<std::pair<uint32_t, uint64_t>> stack{{0u, image.root_addr}};
    while (!stack.empty()) {
      const auto [i, addr] = stack.back();
      stack.pop_back();
      node_at_slot_[(addr - image.nodes.base_addr) / DflLayout::kNodeBytes] = i;
      const KdNode& n = tree.nodes[i];
      if (n.is_leaf()) continue;
      const NodeView v = DflLayout::decode(image, addr);
      stack.push_back({n.below, v.below_addr});
      stack.push_back({n.above, v.above_addr});
    }
  }
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override {
    for (size_t i = 0; i < rays.size(); ++i)
      hits[i] = traverse<DflLayout>(image_, rays[i].ray, rays[i].any_hit(), *this);
  }
  void fetch(Stream s, uint64_t addr, uint32_t) {
    if (s == Stream::kNode)
      ++visits_[node_at_slot_[(addr - image_.nodes.base_addr) / DflLayout::kNodeBytes]];
  }
  std::vector<uint64_t> take() { return std::move(visits_); }

 private:
  const MemoryImage& image_;
  std::vector<uint32_t> node_at_slot_;
  std::vector<uint64_t> visits_;
};

}  // namespace

std::vector<uint64_t> profile_training_visits(const KdTree& tree, const Scene& scene,
                                              const CameraDesc& camera, const TracerParams& tracer) {
  const MemoryImage dfl = DflLayout().build_image(tree, scene);
  VisitCounter counter(tree, dfl);
  WhittedTracer(scene, tracer, counter)
      .render(PinholeCamera(ProfileLayout::training_camera(camera, tree.bounds), ProfileLayout::kTrainingSize, ProfileLayout::kTrainingSize),
              ProfileLayout::kTrainingSize, ProfileLayout::kTrainingSize);
  return counter.take();
}

}  // namespace rtusim
