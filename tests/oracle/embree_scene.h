// A thin Embree 3 wrapper for tests and benchmarks only: the correctness and speed oracle.
#pragma once
#include <embree3/rtcore.h>

#include <limits>
#include <stdexcept>

#include "geom/ray.h"
#include "scene/scene.h"

namespace rtusim::oracle {

class EmbreeScene {
 public:
  explicit EmbreeScene(const Scene& s) {
    device_ = rtcNewDevice("threads=1");
    if (!device_) throw std::runtime_error("rtcNewDevice failed");
    scene_ = rtcNewScene(device_);
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), s.positions.size()));
    for (size_t i = 0; i < s.positions.size(); ++i)
      for (int a = 0; a < 3; ++a) vb[3 * i + a] = s.positions[i][a];
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), s.triangles.size()));
    for (size_t i = 0; i < s.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) ib[3 * i + k] = s.triangles[i][k];
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene_, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene_);
    rtcInitIntersectContext(&context_);
  }
  ~EmbreeScene() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Closest hit with rtcIntersect1 over (0, ray.t_max).
  Hit intersect(const Ray& r) {
    RTCRayHit rh;
    rh.ray.org_x = r.origin.x;
    rh.ray.org_y = r.origin.y;
    rh.ray.org_z = r.origin.z;
    rh.ray.dir_x = r.dir.x;
    rh.ray.dir_y = r.dir.y;
    rh.ray.dir_z = r.dir.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = r.t_max;
    rh.ray.mask = 0xffffffffu;
    rh.ray.flags = 0;
    rh.ray.time = 0.0f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context_, &rh);
    Hit h;
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) h = {rh.ray.tfar, rh.hit.primID, rh.hit.u, rh.hit.v};
    return h;
  }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  RTCIntersectContext context_;
};

}  // namespace rtusim::oracle
