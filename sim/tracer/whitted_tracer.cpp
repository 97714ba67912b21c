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

// A ray-tree node's place: what its contribution is scaled by, and its position in the tree.
struct WhittedTracer::PathState {
  glm::vec3 weight{1.0f};
  int depth = 0;
  uint64_t key = 0;  // pre-order position in the pixel's ray tree
};

// A ray of the ray tree with what its pixel needs to accumulate it.
struct WhittedTracer::PathRay {
  RayRecord rec;
  PathState st;
};

// What hits spawn, appended hit after hit: shadow rays (one per light facing the surface), the
// lit terms they gate, and up to two secondary rays per hit.
struct WhittedTracer::Spawned {
  std::vector<RayRecord> shadow_rays;
  std::vector<glm::vec3> shadow_terms;  // added when shadow_rays[i] is unoccluded
  std::vector<PathRay> secondary;       // per hit: reflection first, then refraction
  std::vector<Hit> shadow_hits;         // recursive order: the shadow rays' hits
  void clear() {
    shadow_rays.clear();
    shadow_terms.clear();
    secondary.clear();
  }
};

// The wavefront order's buffers, kept from one generation (and call) to the next.
struct WhittedTracer::Wavefront {
  // A ray's contribution to its pixel, summed in (pixel, key) order.
  struct Contribution {
    uint32_t pixel;
    uint64_t key;
    glm::vec3 value;
  };
  // One block of kBlockRays consecutive rays of a generation, shaded on any thread.
  struct Block {
    Spawned spawned;
    // Per ray: emission + ambient of its hit; in the first generation then its contribution.
    std::vector<glm::vec3> base;
    std::vector<uint32_t> shadows;    // per ray: its shadow rays
    std::array<uint64_t, kRayKinds> kinds{};
    size_t shadow_begin = 0;     // the block's first shadow ray in the generation's shadow batch
    size_t secondary_begin = 0;  // its first spawned ray in the next generation
    std::vector<Contribution> later;  // contributions of a generation after the first
  };
  static constexpr size_t kBlockRays = 1024;

  std::vector<RayRecord> rays;  // the generation: the batch the backend takes
  std::vector<PathState> states;  // empty in the first generation: every ray is a root
  std::vector<Hit> hits;
  std::vector<Block> blocks;
  std::vector<RayRecord> shadow_rays;  // the generation's shadow batch
  std::vector<Hit> shadow_hits;
  std::vector<Contribution> later;
  std::vector<RayRecord> next_rays;
  std::vector<PathState> next_states;
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
  recursive_spawned_.resize(std::max(0, params_.max_depth) + 1);
  wavefront_ = std::make_unique<Wavefront>();
}

WhittedTracer::~WhittedTracer() = default;

glm::vec3 WhittedTracer::shade(const RayRecord& rec, const PathState& st, const Hit& hit,
                               Spawned& out) const {
  const auto& tri = scene_.triangles[hit.triangle];
  const Material& m = scene_.materials[scene_.triangle_material[hit.triangle]];
  const auto v = scene_.vertices(hit.triangle);
  const float w0 = 1.0f - hit.u - hit.v;
  const glm::vec3 p = w0 * v[0] + hit.u * v[1] + hit.v * v[2];
  const glm::vec3 d = glm::normalize(rec.ray.dir);

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
  const glm::vec3 base_local = m.emissive + params_.ambient * m.base_color;
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
    shadow.pixel = rec.pixel;
    out.shadow_rays.push_back(shadow);
    out.shadow_terms.push_back(kd * cos_l * m.base_color * light.color * light.intensity);
  }
  if (st.depth >= params_.max_depth) return base_local;

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
    child.st.weight = st.weight * weight;
    if (max3(child.st.weight) <= 0.0f) return;
    child.rec.ray = {origin, dir, std::numeric_limits<float>::infinity()};
    child.rec.kind = kind;
    child.rec.pixel = rec.pixel;
    child.st.depth = st.depth + 1;
    child.st.key = st.key + digit * key_step_[child.st.depth];
    out.secondary.push_back(child);
  };
  if (max3(w_reflect) > 0.0f) {
    glm::vec3 r = d + 2.0f * cos_i * ns;
    if (glm::dot(r, nf) <= 0.0f) r = d - 2.0f * glm::dot(d, nf) * nf;  // keep it outside
    spawn(w_reflect, p_out, glm::normalize(r), RayKind::kReflection, 1);
  }
  if (max3(w_refract) > 0.0f) spawn(w_refract, p_in, refract_dir, RayKind::kRefraction, 2);
  return base_local;
}

glm::vec3 WhittedTracer::local_radiance(glm::vec3 base, const glm::vec3* terms,
                                        const Hit* shadow_hits, size_t n) {
  glm::vec3 c = base;
  for (size_t i = 0; i < n; ++i)
    if (!shadow_hits[i].valid()) c += terms[i];
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
    acc += pr.st.weight * params_.background;
    return;
  }
  // This depth's buffers: the children below use the next depth's.
  Spawned& sp = recursive_spawned_[pr.st.depth];
  sp.clear();
  const glm::vec3 base = shade(pr.rec, pr.st, hit, sp);
  const size_t n = sp.shadow_rays.size();
  sp.shadow_hits.assign(n, Hit{});
  for (size_t i = 0; i < n; ++i) backend_.trace({&sp.shadow_rays[i], 1}, {&sp.shadow_hits[i], 1});
  out.rays_by_kind[static_cast<int>(RayKind::kShadow)] += n;
  acc += pr.st.weight * local_radiance(base, sp.shadow_terms.data(), sp.shadow_hits.data(), n);
  for (const PathRay& child : sp.secondary) trace_recursive(child, out, acc);
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
// then the next generation. Contributions are summed per pixel in ray-tree pre-order: the first
// generation's (key 0, first in every tree) at once, the later ones sorted at the end.
// Generation, shading and gathering run in blocks of consecutive rays on every thread; the
// batches keep the generation's order.
void WhittedTracer::render_wavefront(const PinholeCamera& camera,
                                     std::span<const uint32_t> pixels, FrameResult& out) {
  using Block = Wavefront::Block;
  using Contribution = Wavefront::Contribution;
  constexpr size_t kBlockRays = Wavefront::kBlockRays;
  Wavefront& wf = *wavefront_;
  // Runs f(block index, first ray, end ray) over the blocks of `n` rays on every thread.
  auto for_blocks = [&](size_t n, auto&& f) {
    const size_t count = (n + kBlockRays - 1) / kBlockRays;
    if (wf.blocks.size() < count) wf.blocks.resize(count);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t b = r.begin(); b != r.end(); ++b)
                          f(b, b * kBlockRays, std::min(n, (b + 1) * kBlockRays));
                      });
    return count;
  };

  // The first generation: a primary ray per pixel.
  wf.rays.resize(pixels.size());
  wf.states.clear();
  for_blocks(pixels.size(), [&](size_t, size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      RayRecord& rec = wf.rays[i];
      rec = RayRecord{};
      rec.ray = camera.generate(static_cast<int>(pixels[i] % out.width),
                                static_cast<int>(pixels[i] / out.width));
      rec.pixel = pixels[i];
    }
  });
  wf.later.clear();

  const PathState root;
  for (bool first = true; !wf.rays.empty(); first = false) {
    const size_t n = wf.rays.size();
    auto state = [&](size_t i) -> const PathState& { return first ? root : wf.states[i]; };
    wf.hits.assign(n, Hit{});
    backend_.trace(wf.rays, wf.hits);

    // Shade every hit, block by block; then trace all of the generation's shadow rays as one
    // batch, in the generation's order.
    const size_t blocks = for_blocks(n, [&](size_t b, size_t begin, size_t end) {
      Block& blk = wf.blocks[b];
      blk.spawned.clear();
      // Room for the most a block can spawn, so that the buffers never grow by copying (the
      // pages are touched only as they fill).
      blk.spawned.shadow_rays.reserve((end - begin) * lights_.size());
      blk.spawned.shadow_terms.reserve((end - begin) * lights_.size());
      blk.spawned.secondary.reserve((end - begin) * 2);
      blk.base.resize(end - begin);
      blk.shadows.assign(end - begin, 0);
      blk.kinds = {};
      for (size_t i = begin; i < end; ++i) {
        ++blk.kinds[static_cast<int>(wf.rays[i].kind)];
        if (!wf.hits[i].valid()) continue;
        const size_t before = blk.spawned.shadow_rays.size();
        blk.base[i - begin] = shade(wf.rays[i], state(i), wf.hits[i], blk.spawned);
        blk.shadows[i - begin] = static_cast<uint32_t>(blk.spawned.shadow_rays.size() - before);
      }
    });
    size_t shadow_total = 0, secondary_total = 0;
    for (size_t b = 0; b < blocks; ++b) {
      Block& blk = wf.blocks[b];
      for (int k = 0; k < kRayKinds; ++k) out.rays_by_kind[k] += blk.kinds[k];
      blk.shadow_begin = shadow_total;
      blk.secondary_begin = secondary_total;
      shadow_total += blk.spawned.shadow_rays.size();
      secondary_total += blk.spawned.secondary.size();
    }
    wf.shadow_rays.resize(shadow_total);
    for_blocks(n, [&](size_t b, size_t, size_t) {
      const Block& blk = wf.blocks[b];
      std::copy(blk.spawned.shadow_rays.begin(), blk.spawned.shadow_rays.end(),
                wf.shadow_rays.begin() + blk.shadow_begin);
    });
    wf.shadow_hits.assign(shadow_total, Hit{});
    backend_.trace(wf.shadow_rays, wf.shadow_hits);
    out.rays_by_kind[static_cast<int>(RayKind::kShadow)] += shadow_total;

    // Each ray's contribution, and the next generation (the blocks' secondary rays in order).
    wf.next_rays.resize(secondary_total);
    wf.next_states.resize(secondary_total);
    for_blocks(n, [&](size_t b, size_t begin, size_t end) {
      Block& blk = wf.blocks[b];
      blk.later.clear();
      const Hit* shadow_hits = wf.shadow_hits.data() + blk.shadow_begin;
      const glm::vec3* terms = blk.spawned.shadow_terms.data();
      for (size_t i = begin; i < end; ++i) {
        const PathState& st = state(i);
        glm::vec3 value;
        if (!wf.hits[i].valid()) {
          value = st.weight * params_.background;
        } else {
          const size_t k = blk.shadows[i - begin];
          value = st.weight * local_radiance(blk.base[i - begin], terms, shadow_hits, k);
          terms += k;
          shadow_hits += k;
        }
        if (first) blk.base[i - begin] = value;
        else blk.later.push_back({wf.rays[i].pixel, st.key, value});
      }
      for (size_t j = 0; j < blk.spawned.secondary.size(); ++j) {
        wf.next_rays[blk.secondary_begin + j] = blk.spawned.secondary[j].rec;
        wf.next_states[blk.secondary_begin + j] = blk.spawned.secondary[j].st;
      }
    });
    if (first) {
      for (size_t i = 0; i < n; ++i)
        out.radiance[wf.rays[i].pixel] += wf.blocks[i / kBlockRays].base[i % kBlockRays];
    } else {
      for (size_t b = 0; b < blocks; ++b)
        wf.later.insert(wf.later.end(), wf.blocks[b].later.begin(), wf.blocks[b].later.end());
    }
    std::swap(wf.rays, wf.next_rays);
    std::swap(wf.states, wf.next_states);
  }

  std::sort(wf.later.begin(), wf.later.end(), [](const Contribution& a, const Contribution& b) {
    return a.pixel != b.pixel ? a.pixel < b.pixel : a.key < b.key;
  });
  for (const Contribution& c : wf.later) out.radiance[c.pixel] += c.value;
}

}  // namespace rtusim
