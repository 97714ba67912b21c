// The profile layout's training: visit counts per logical kd-tree node, measured by tracing the
// training frame (ProfileLayout::training_camera, kTrainingSize^2 pixels, the run's tracer
// settings) over a DFL image of the same tree. Lives in app/ because it drives the tracer.
#pragma once
#include <cstdint>
#include <vector>

#include "kdtree/kd_tree.h"
#include "scene/scene.h"
#include "tracer/tracer_params.h"

namespace rtusim {

std::vector<uint64_t> profile_training_visits(const KdTree& tree, const Scene& scene,
                                              const CameraDesc& camera, const TracerParams& tracer);

}  // namespace rtusim
