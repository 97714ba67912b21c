// Whitted tracing in two ray orders that give bit-identical images: every ray-tree node adds
// one contribution (weight x local radiance, or weight x background on a miss), and both orders
// sum a pixel's contributions in the ray tree's pre-order.
#include "tracer/whitted_tracer.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

namespace rtusim {

// A ray of the ray tree with what its pixel needs to accumulate it.
struct WhittedTracer::PathRay {
  RayRecord rec;
  glm::vec3 weight{1.0f};
  int depth = 0;
  uint64_t key = 0;  // pre-order position in the pixel's ray tree
};

// What a hit spawns: shadow rays (one per light facing the surface), the lit terms they gate,
// and up to two secondary rays.
struct WhittedTracer::Shading {
  glm::vec3 base_local{0.0f};  // emission + ambient
  std::vector<RayRecord> shadow_rays;
  std::vector<glm::vec3> shadow_terms;  // added when shadow_rays[i] is unoccluded
  std::vector<PathRay> secondary;       // reflection first, then refraction
};

namespace {

float max3(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

// Unpolarised Fresnel reflectance of a dielectric; 1 under total internal reflection.
float fresnel_dielectric(float cos_i, float eta_i, float eta_t) {
  const float sin_t = eta_i / eta_t * std::sqrt(std::max(0.0f, 1.0f - cos_i * cos_i));
  if (sin_t >= 1.0f) return 1.0f;
  const float cos_t = std::sqrt(std::max(0.0f, 1.0f - sin_t * sin_t));
  const float rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
  const float rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

}  // namespace

WhittedTracer::WhittedTracer(const Scene& scene, const TracerParams& params,
                             TraceBackend& backend)
    : scene_(scene), params_(params), backend_(backend),
      offset_(scene.bounds().max_abs_coord()) {
  // Key strides: a child at depth d adds 1 (reflection) or 2 (refraction) x 3^(max_depth - d).
  key_step_.assign(params_.max_depth + 2, 0);
  uint64_t p = 1;
  for (int d = params_.max_depth; d >= 1; --d, p *= 3) key_step_[d] = p;
}

WhittedTracer::Shading WhittedTracer::shade(const PathRay& pr, const Hit& hit) const {
  Shading sh;
  const auto& tri = scene_.triangles[hit.triangle];
  const Material& m = scene_.materials[scene_.triangle_material[hit.triangle]];
  const auto v = scene_.vertices(hit.triangle);
  const float w0 = 1.0f - hit.u - hit.v;
  const glm::vec3 p = w0 * v[0] + hit.u * v[1] + hit.v * v[2];
  const glm::vec3 d = glm::normalize(pr.rec.ray.dir);

  // Face normal towards the incoming ray; shading normal from vertex normals where present.
  glm::vec3 ng = glm::cross(v[1] - v[0], v[2] - v[0]);
  const float ng_len = glm::length(ng);
  ng = ng_len > 0.0f ? ng / ng_len : -d;
  const bool front = glm::dot(ng, d) < 0.0f;
  const glm::vec3 nf = front ? ng : -ng;
  const glm::vec3& n0 = scene_.normals[tri[0]];
  const glm::vec3& n1 = scene_.normals[tri[1]];
  const glm::vec3& n2 = scene_.normals[tri[2]];
  glm::vec3 ns = nf;
  if (n0 != glm::vec3(0.0f) && n1 != glm::vec3(0.0f) && n2 != glm::vec3(0.0f)) {
    const glm::vec3 interp = w0 * n0 + hit.u * n1 + hit.v * n2;
    if (glm::length(interp) > 0.0f) ns = glm::normalize(interp);
    if (glm::dot(ns, nf) < 0.0f) ns = -ns;
  }
  const glm::vec3 p_out = offset_.offset(p, nf);  // origin for rays leaving on the ray's side
  const glm::vec3 p_in = offset_.offset(p, -nf);  // origin for rays entering the surface

  // Local terms: emission and ambient, then each point light through a shadow ray.
  const bool mirror = m.metallic >= params_.mirror_threshold;
  const float kd = (1.0f - m.transmission) * (mirror ? 1.0f - m.metallic : 1.0f);
  sh.base_local = m.emissive + params_.ambient * m.base_color;
  for (const PointLight& light : lights_) {
    const glm::vec3 to_light = light.position - p_out;
    const float dist = glm::length(to_light);
    if (!(dist > 0.0f)) continue;
    const glm::vec3 l = to_light / dist;
    const float cos_l = glm::dot(ns, l);
    if (cos_l <= 0.0f || glm::dot(nf, l) <= 0.0f || kd <= 0.0f) continue;
    RayRecord shadow;
    shadow.ray = {p_out, l, dist};
    shadow.kind = RayKind::kShadow;
    shadow.pixel = pr.rec.pixel;
    sh.shadow_rays.push_back(shadow);
    sh.shadow_terms.push_back(kd * cos_l * m.base_color * light.color * light.intensity);
  }
  if (pr.depth >= params_.max_depth) return sh;

  // Secondary rays: mirror reflection for metals, Fresnel reflection + refraction for glass.
  const float cos_i = std::min(1.0f, -glm::dot(d, ns));
  glm::vec3 w_reflect = mirror ? m.metallic * m.base_color : glm::vec3(0.0f);
  glm::vec3 w_refract(0.0f);
  glm::vec3 refract_dir(0.0f);
  if (m.transmission > 0.0f) {
    const float eta_i = front ? 1.0f : m.ior, eta_t = front ? m.ior : 1.0f;
    const float f = fresnel_dielectric(cos_i, eta_i, eta_t);
    w_reflect += glm::vec3(f * m.transmission);
    if (f < 1.0f) {
      const float eta = eta_i / eta_t;
      const float k = 1.0f - eta * eta * (1.0f - cos_i * cos_i);
      refract_dir = glm::normalize(eta * d + (eta * cos_i - std::sqrt(std::max(0.0f, k))) * ns);
      if (glm::dot(refract_dir, nf) >= 0.0f) refract_dir = -nf;  // shading-normal artefact
      w_refract = glm::vec3((1.0f - f) * m.transmission) * m.base_color;
    }
  }
  auto spawn = [&](const glm::vec3& weight, const glm::vec3& origin, const glm::vec3& dir,
                   RayKind kind, uint64_t digit) {
    PathRay child;
    child.weight = pr.weight * weight;
    if (max3(child.weight) <= 0.0f) return;
    child.rec.ray = {origin, dir, std::numeric_limits<float>::infinity()};
    child.rec.kind = kind;
    child.rec.pixel = pr.rec.pixel;
    child.depth = pr.depth + 1;
    child.key = pr.key + digit * key_step_[child.depth];
    sh.secondary.push_back(child);
  };
  if (max3(w_reflect) > 0.0f) {
    glm::vec3 r = d + 2.0f * cos_i * ns;
    if (glm::dot(r, nf) <= 0.0f) r = d - 2.0f * glm::dot(d, nf) * nf;  // keep it outside
    spawn(w_reflect, p_out, glm::normalize(r), RayKind::kReflection, 1);
  }
  if (max3(w_refract) > 0.0f) spawn(w_refract, p_in, refract_dir, RayKind::kRefraction, 2);
  return sh;
}

glm::vec3 WhittedTracer::local_radiance(const Shading& sh, const Hit* shadow_hits) const {
  glm::vec3 c = sh.base_local;
  for (size_t i = 0; i < sh.shadow_rays.size(); ++i)
    if (!shadow_hits[i].valid()) c += sh.shadow_terms[i];
  return c;
}

FrameResult WhittedTracer::render(const PinholeCamera& camera, int width, int height) {
  FrameResult out = begin_frame(camera, width, height);
  std::vector<uint32_t> pixels(size_t(width) * height);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<uint32_t>(i);
  render_pixels(camera, pixels, out);
  return out;
}

FrameResult WhittedTracer::begin_frame(const PinholeCamera& camera, int width, int height) {
  lights_ = scene_.lights;
  if (lights_.empty() && params_.headlight)
    lights_.push_back(PointLight{"headlight", camera.eye(), glm::vec3(1.0f), 1.0f});
  FrameResult out;
  out.width = width;
  out.height = height;
  out.radiance.assign(size_t(width) * height, glm::vec3(0.0f));
  return out;
}

void WhittedTracer::render_pixels(const PinholeCamera& camera, std::span<const uint32_t> pixels,
                                  FrameResult& out) {
  if (params_.order == RayOrder::kRecursive) render_recursive(camera, pixels, out);
  else render_wavefront(camera, pixels, out);
}

// Recursive order: one pixel at a time, its ray tree depth first (shadow rays of a hit before
// its reflection, reflection subtree before refraction subtree).
void WhittedTracer::trace_recursive(const PathRay& pr, FrameResult& out, glm::vec3& acc) {
  Hit hit;
  backend_.trace({&pr.rec, 1}, {&hit, 1});
  ++out.rays_by_kind[static_cast<int>(pr.rec.kind)];
  if (!hit.valid()) {
    acc += pr.weight * params_.background;
    return;
  }
  const Shading sh = shade(pr, hit);
  std::vector<Hit> shadow_hits(sh.shadow_rays.size());
  for (size_t i = 0; i < sh.shadow_rays.size(); ++i)
    backend_.trace({&sh.shadow_rays[i], 1}, {&shadow_hits[i], 1});
  out.rays_by_kind[static_cast<int>(RayKind::kShadow)] += sh.shadow_rays.size();
  acc += pr.weight * local_radiance(sh, shadow_hits.data());
  for (const PathRay& child : sh.secondary) trace_recursive(child, out, acc);
}

void WhittedTracer::render_recursive(const PinholeCamera& camera,
                                     std::span<const uint32_t> pixels, FrameResult& out) {
  for (const uint32_t pixel : pixels) {
    PathRay pr;
    pr.rec.ray = camera.generate(static_cast<int>(pixel % out.width),
                                 static_cast<int>(pixel / out.width));
    pr.rec.pixel = pixel;
    glm::vec3 acc(0.0f);
    trace_recursive(pr, out, acc);
    out.radiance[pr.rec.pixel] = acc;
  }
}

// Wavefront order: every ray of one generation as a batch, then that generation's shadow rays,
// then the next generation. Contributions are summed per pixel in ray-tree pre-order.
void WhittedTracer::render_wavefront(const PinholeCamera& camera,
                                     std::span<const uint32_t> pixels, FrameResult& out) {
  struct Contribution {
    uint32_t pixel;
    uint64_t key;
    glm::vec3 value;
  };
  std::vector<Contribution> contributions;
  std::vector<PathRay> generation;
  generation.reserve(pixels.size());
  for (const uint32_t pixel : pixels) {
    PathRay pr;
    pr.rec.ray = camera.generate(static_cast<int>(pixel % out.width),
                                 static_cast<int>(pixel / out.width));
    pr.rec.pixel = pixel;
    generation.push_back(pr);
  }

  std::vector<RayRecord> batch;
  std::vector<Hit> hits;
  while (!generation.empty()) {
    batch.clear();
    for (const PathRay& pr : generation) batch.push_back(pr.rec);
    hits.assign(batch.size(), Hit{});
    backend_.trace(batch, hits);
    for (const RayRecord& r : batch) ++out.rays_by_kind[static_cast<int>(r.kind)];

    // Shade every hit (each on its own: on every thread), then trace all of the generation's
    // shadow rays as one batch, in the generation's order.
    std::vector<Shading> shadings(generation.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, generation.size(), 1024),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t i = r.begin(); i != r.end(); ++i)
                          if (hits[i].valid()) shadings[i] = shade(generation[i], hits[i]);
                      });
    std::vector<RayRecord> shadow_batch;
    for (const Shading& sh : shadings)
      shadow_batch.insert(shadow_batch.end(), sh.shadow_rays.begin(), sh.shadow_rays.end());
    std::vector<Hit> shadow_hits(shadow_batch.size());
    backend_.trace(shadow_batch, shadow_hits);
    out.rays_by_kind[static_cast<int>(RayKind::kShadow)] += shadow_batch.size();

    std::vector<PathRay> next;
    size_t s = 0;
    for (size_t i = 0; i < generation.size(); ++i) {
      const PathRay& pr = generation[i];
      if (!hits[i].valid()) {
        contributions.push_back({pr.rec.pixel, pr.key, pr.weight * params_.background});
        continue;
      }
      const Shading& sh = shadings[i];
      contributions.push_back({pr.rec.pixel, pr.key,
                               pr.weight * local_radiance(sh, shadow_hits.data() + s)});
      s += sh.shadow_rays.size();
      next.insert(next.end(), sh.secondary.begin(), sh.secondary.end());
    }
    generation = std::move(next);
  }

  std::sort(contributions.begin(), contributions.end(), [](const auto& a, const auto& b) {
    return a.pixel != b.pixel ? a.pixel < b.pixel : a.key < b.key;
  });
  for (const Contribution& c : contributions) out.radiance[c.pixel] += c.value;
}

}  // namespace rtusim
