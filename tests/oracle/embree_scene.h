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

  // Closest hits of rays r[0, n) (n <= 16) as one packet with rtcIntersect16, each over
  // (0, t_max); lanes past n are invalid.
  void intersect16(const Ray* r, int n, Hit* out) {
    alignas(64) int valid[16];
    alignas(64) RTCRayHit16 rh;
    for (int i = 0; i < 16; ++i) {
      valid[i] = i < n ? -1 : 0;
      const Ray& ray = r[i < n ? i : 0];
      rh.ray.org_x[i] = ray.origin.x;
      rh.ray.org_y[i] = ray.origin.y;
      rh.ray.org_z[i] = ray.origin.z;
      rh.ray.dir_x[i] = ray.dir.x;
      rh.ray.dir_y[i] = ray.dir.y;
      rh.ray.dir_z[i] = ray.dir.z;
      rh.ray.tnear[i] = 0.0f;
      rh.ray.tfar[i] = ray.t_max;
      rh.ray.mask[i] = 0xffffffffu;
      rh.ray.flags[i] = 0;
      rh.ray.time[i] = 0.0f;
      rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, scene_, &context_, &rh);
    for (int i = 0; i < n; ++i) {
      out[i] = Hit{};
      if (rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID)
        out[i] = {rh.ray.tfar[i], rh.hit.primID[i], rh.hit.u[i], rh.hit.v[i]};
    }
  }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  RTCIntersectContext context_;
};

}  // namespace rtusim::oracle
