// The watertight triangle test at its failure points, against a long-double reference from the
// same float inputs: origins exactly on the triangle's plane (the exact t is 0: never a hit),
// hits very close to the origin and grazing rays (t's relative error bounded, no hit lost).
#include "traversal/watertight_triangle.h"

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace rtusim {
namespace {

using Vec = glm::vec3;

// Exact-input reference: t of the ray's crossing of the plane and the barycentrics there, in
// long double (80-bit) from the float vertices, origin and direction.
struct Reference {
  long double t = 0, u = 0, v = 0;
};
Reference reference(const Vec& o, const Vec& d, const Vec& a, const Vec& b, const Vec& c) {
  using L = long double;
  const L e1[3] = {L(b.x) - a.x, L(b.y) - a.y, L(b.z) - a.z};
  const L e2[3] = {L(c.x) - a.x, L(c.y) - a.y, L(c.z) - a.z};
  const L n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                  e1[0] * e2[1] - e1[1] * e2[0]};
  const L w[3] = {L(a.x) - o.x, L(a.y) - o.y, L(a.z) - o.z};
  Reference r;
  r.t = (n[0] * w[0] + n[1] * w[1] + n[2] * w[2]) / (n[0] * d.x + n[1] * d.y + n[2] * d.z);
  // Barycentrics of the hit point p = o + t d: p - a = u e1 + v e2, solved with n.
  const L p[3] = {L(o.x) + r.t * d.x - a.x, L(o.y) + r.t * d.y - a.y, L(o.z) + r.t * d.z - a.z};
  const L nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  auto cross_dot = [&](const L* x, const L* y) {  // (x cross y) . n
    return (x[1] * y[2] - x[2] * y[1]) * n[0] + (x[2] * y[0] - x[0] * y[2]) * n[1] +
           (x[0] * y[1] - x[1] * y[0]) * n[2];
  };
  r.u = cross_dot(p, e2) / nn;
  r.v = cross_dot(e1, p) / nn;
  return r;
}

bool hit(const Vec& o, const Vec& d, const Vec& a, const Vec& b, const Vec& c, float& t) {
  float u, v;
  return intersect_watertight(WatertightRay(o, d), a, b, c, 1e30f, t, u, v);
}

// A float with few mantissa bits (a multiple of 1/1024 in [-8, 8]): sums of two stay exact.
float coarse(std::mt19937& rng) {
  return static_cast<float>(static_cast<int>(rng() % 16384) - 8192) / 1024.0f;
}

// Origins exactly on tilted planes x + y + z = k (each point's z is the exact -(x + y) + k):
// the exact t is 0, so no direction may report a hit.
TEST(WatertightTest, OriginOnThePlaneNeverHits) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  int cases = 0, hits = 0;
  for (int i = 0; i < 200000; ++i) {
    const float k = coarse(rng);
    auto on_plane = [&](float x, float y) { return Vec(x, y, k - (x + y)); };
    const Vec a = on_plane(coarse(rng), coarse(rng)), b = on_plane(coarse(rng), coarse(rng)),
              c = on_plane(coarse(rng), coarse(rng));
    // The origin: a point of the plane inside the triangle's bounding range.
    const Vec o = on_plane((a.x + b.x + c.x > 0 ? 1.0f : -1.0f) * float(rng() % 64) / 256.0f + a.x,
                           float(rng() % 64) / 256.0f + a.y);
    const Vec d = glm::normalize(Vec(unit(rng), unit(rng), unit(rng)));
    float t;
    ++cases;
    if (hit(o, d, a, b, c, t)) {
      ++hits;
      ADD_FAILURE() << "hit at t = " << t << " from an origin on the plane (case " << i << ")";
      if (hits > 5) break;
    }
  }
  EXPECT_EQ(hits, 0) << "of " << cases;
}

// Hits close to the origin (t from 1e-6 to 1e-2, scene scale ~1..10): t within 0.1 % of the
// reference, and every hit the reference has well inside the triangle is found.
TEST(WatertightTest, NearHitsHaveBoundedRelativeError) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), pos(-10.0f, 10.0f);
  int checked = 0;
  double worst = 0;
  for (int i = 0; i < 200000; ++i) {
    const Vec a(pos(rng), pos(rng), pos(rng)), b(pos(rng), pos(rng), pos(rng)),
        c(pos(rng), pos(rng), pos(rng));
    // A point inside the triangle, an origin a small distance back along a random direction.
    const float wu = std::uniform_real_distribution<float>(0.1f, 0.8f)(rng);
    const float wv = std::uniform_real_distribution<float>(0.05f, 0.9f - wu)(rng);
    const Vec p = a + wu * (b - a) + wv * (c - a);
    const Vec d = glm::normalize(Vec(unit(rng), unit(rng), unit(rng)));
    const float dist = std::pow(10.0f, std::uniform_real_distribution<float>(-6.0f, -2.0f)(rng));
    const Vec o = p - dist * d;
    const Reference ref = reference(o, d, a, b, c);
    if (!(ref.t > 0) || ref.u < 0.01L || ref.v < 0.01L || ref.u + ref.v > 0.99L) continue;
    float t;
    ASSERT_TRUE(hit(o, d, a, b, c, t)) << "lost a hit at reference t = " << double(ref.t);
    const double rel = std::abs(double(t) - double(ref.t)) / double(ref.t);
    worst = std::max(worst, rel);
    ASSERT_LE(rel, 1e-3) << "t = " << t << ", reference " << double(ref.t);
    ++checked;
  }
  EXPECT_GT(checked, 100000);
  RecordProperty("worst_relative_error", std::to_string(worst));
}

// Grazing rays (1e-4 to 1e-2 rad off the plane): same bounds.
TEST(WatertightTest, GrazingHitsHaveBoundedRelativeError) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), pos(-10.0f, 10.0f);
  int checked = 0;
  for (int i = 0; i < 100000; ++i) {
    const Vec a(pos(rng), pos(rng), pos(rng)), b(pos(rng), pos(rng), pos(rng)),
        c(pos(rng), pos(rng), pos(rng));
    const Vec n = glm::normalize(glm::cross(b - a, c - a));
    const Vec p = a + 0.3f * (b - a) + 0.3f * (c - a);
    Vec in_plane = glm::cross(n, Vec(unit(rng), unit(rng), unit(rng)));
    if (glm::length(in_plane) < 0.1f) continue;
    in_plane = glm::normalize(in_plane);
    const float angle = std::pow(10.0f, std::uniform_real_distribution<float>(-4.0f, -2.0f)(rng));
    const Vec d = glm::normalize(std::cos(angle) * in_plane - std::sin(angle) * n);
    const Vec o = p - std::uniform_real_distribution<float>(0.01f, 5.0f)(rng) * d;
    const Reference ref = reference(o, d, a, b, c);
    if (!(ref.t > 0) || ref.u < 0.01L || ref.v < 0.01L || ref.u + ref.v > 0.99L) continue;
    float t;
    ASSERT_TRUE(hit(o, d, a, b, c, t)) << "lost a grazing hit at reference t = " << double(ref.t);
    ASSERT_LE(std::abs(double(t) - double(ref.t)) / double(ref.t), 1e-3);
    ++checked;
  }
  EXPECT_GT(checked, 10000);
}

// Scenes in large units: T = t * det grows as the cube of the coordinates and overflows float
// from ~1e12 on while t does not; such hits must not be lost (they were from 3e12 to 1e14).
TEST(WatertightTest, HitsAtLargeScalesAreKept) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), inside(0.1f, 0.4f);
  for (const float scale : {1.0f, 1e6f, 1e11f, 1e12f, 3e12f, 1e13f, 1e14f, 1e15f, 1e16f, 1e18f}) {
    for (int i = 0; i < 200; ++i) {
      const Vec a = scale * Vec(unit(rng), unit(rng), unit(rng));
      const Vec b = a + scale * Vec(1.0f, unit(rng) * 0.2f, 0.1f * unit(rng));
      const Vec c = a + scale * Vec(unit(rng) * 0.2f, 1.0f, 0.1f * unit(rng));
      const Vec p = a + inside(rng) * (b - a) + inside(rng) * (c - a);
      const Vec o = p + scale * Vec(unit(rng), unit(rng), 4.0f);
      const Vec d = glm::normalize(p - o);
      const Reference ref = reference(o, d, a, b, c);
      float t;
      ASSERT_TRUE(hit(o, d, a, b, c, t)) << "scale " << scale << ": lost the hit at t = "
                                         << double(ref.t);
      ASSERT_LE(std::abs(double(t) - double(ref.t)) / double(ref.t), 1e-3) << "scale " << scale;
    }
  }
}

}  // namespace
}  // namespace rtusim
