// The tracer's keys (tracer.*).
#include "tracer/tracer_params.h"

#include "config/param.h"

namespace rtusim {
namespace {

const TracerParams kDefaults;
const IntParam kMaxDepth("tracer.max_depth", kDefaults.max_depth, 0, 16, "bounces",
                         "secondary bounces after the primary hit");
const StringParam kRayOrder("tracer.ray_order", "recursive", {"recursive", "wavefront"}, "",
                            "recursive: each pixel's ray tree depth first (the paper); "
                            "wavefront: generation by generation");
const FloatParam kMirrorThreshold("tracer.mirror_threshold", kDefaults.mirror_threshold, 0.0,
                                  1.0, "", "metallic at or above this reflects");
const FloatParam kAmbient("tracer.ambient", 0.1, 0.0, 1e6, "",
                          "ambient term times base colour");
const Vec3Param kBackground("tracer.background", kDefaults.background, "linear RGB",
                            "colour of a ray that hits nothing");
const BoolParam kHeadlight("tracer.headlight", kDefaults.headlight,
                           "a point light at the eye when the scene has none");

}  // namespace

TracerParams read_tracer_params(ConfigReader& r) {
  TracerParams t;
  t.max_depth = static_cast<int>(kMaxDepth.read(r));
  t.order = kRayOrder.read(r) == "wavefront" ? RayOrder::kWavefront : RayOrder::kRecursive;
  t.mirror_threshold = static_cast<float>(kMirrorThreshold.read(r));
  t.ambient = static_cast<float>(kAmbient.read(r));
  t.background = *kBackground.read(r);
  t.headlight = kHeadlight.read(r);
  return t;
}

}  // namespace rtusim
