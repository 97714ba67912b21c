#include "sample/sampled_frame.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "sample/generation_sampler.h"
#include "tracer/hit_backend.h"
#include "tracer/parallel_render.h"
#include "util/error.h"
#include "util/stat_decl.h"

namespace rtusim {
namespace {
// Stats keys of a sampled run (each counter also gets .ci95_low and .ci95_high).
const StatDecl kAchievedCi("sample.achieved_ci", StatKind::kRatio, "",
                           "relative 95% half-width of the target key");
const StatDecl kAchievedCiKey("sample.achieved_ci_key", StatKind::kProperty, "",
                              "the key sample.achieved_ci is of");
const StatDecl kRaysSimulated("sample.rays_simulated", StatKind::kProperty, "rays",
                              "rays traced in the sampled units");
const StatDecl kRaysWarmed("sample.rays_warmed", StatKind::kProperty, "rays",
                           "rays traced to warm the caches, unmeasured");
const StatDecl kRaysSimulatedPerSecond("sample.rays_simulated_per_second", StatKind::kTiming,
                                       "rays/s", "sampled rays per second of wall time");
const StatDecl kMethod("sample.method", StatKind::kProperty, "",
                       "the run's sample.method");
const StatDecl kRate("sample.rate", StatKind::kProperty, "",
                     "the run's sample.rate");
const StatDecl kSeed("sample.seed", StatKind::kProperty, "",
                     "the run's sample.seed");
const StatDecl kWarmup("sample.warmup", StatKind::kProperty, "",
                       "the run's sample.warmup");
const StatDecl kEstimator("sample.estimator", StatKind::kProperty, "",
                          "the run's sample.estimator");
const StatDecl kTargetCi("sample.target_ci", StatKind::kProperty, "",
                         "the run's sample.target_ci");
const StatDecl kUnits("sample.units", StatKind::kProperty, "units",
                      "units simulated");
const StatDecl kUnitsTotal("sample.units_total", StatKind::kProperty, "units",
                           "units of the frame");
const StatDecl kRounds("sample.rounds", StatKind::kProperty, "rounds",
                       "rounds drawn");
const StatDecl kPixels("sample.pixels", StatKind::kProperty, "pixels",
                       "pixels simulated");
const StatDecl kFraction("sample.fraction", StatKind::kRatio, "",
                         "sample.pixels / the frame's pixels");
const StatDecl kCiValid("sample.ci_valid", StatKind::kProperty, "",
                        "the intervals are valid (enough units)");
const StatDecl kProblem("sample.problem", StatKind::kProperty, "",
                      "why they are not, or """);
const StatDecl kTargetMet("sample.target_met", StatKind::kProperty, "",
                          "sample.target_ci was met");
const StatDecl kPerGeneration("sample.per_generation", StatKind::kProperty, "",
                              "units sampled per generation (wavefront)");

const char* const kRayKeys[kRayKinds] = {"rays.primary", "rays.shadow", "rays.reflection",
                                         "rays.refraction"};

// Figures whose layout differences get a paired CI.
const char* const kPairedKeys[] = {"dram.bytes.nodes", "dram.bytes.total", "l1.misses",
                                   "sim.cycles", "estimate.cycles"};

// The cycle tier's unit and DRAM counters: sums over rays and requests like the others.
bool is_ray_key(const std::string& key) {
  return key == "rays.total" || std::find(std::begin(kRayKeys), std::end(kRayKeys), key) !=
                                    std::end(kRayKeys);
}

}  // namespace

void SampledFrame::add_extensive_change(const Stats& before, const Stats& after,
                                        std::map<std::string, double>& into) {
  for (const auto& [key, value] : after.values())
    if (is_counter_key(key) && value.is_number())
      into[key] += value.get<double>() - before.at(key).get<double>();
}

SampledFrame::SampledFrame(const SampleParams& params, int width, int height, RayOrder order)
    : params_(params), width_(width), height_(height), order_(order),
      plan_(make_unit_plan(params, width, height)),
      estimator_(plan_.stratum_units, params.min_units) {}

std::vector<uint32_t> SampledFrame::round_units(size_t from, size_t to) const {
  std::vector<uint32_t> units(plan_.order.begin() + from, plan_.order.begin() + to);
  std::sort(units.begin(), units.end(),
            [&](uint32_t a, uint32_t b) { return plan_.units[a][0] < plan_.units[b][0]; });
  return units;
}

void SampledFrame::trace_generations(const Scene& scene, const TracerParams& tracer,
                                     const PinholeCamera& camera, TierRun& tier,
                                     const MemoryImage& image, size_t from, size_t to,
                                     FrameResult& frame, LayoutSample& sample) {
  const std::vector<uint32_t> units = round_units(from, to);
  std::vector<int32_t> unit_of_pixel(size_t(width_) * height_, -1);
  for (size_t k = 0; k < units.size(); ++k)
    for (const uint32_t p : plan_.units[units[k]]) unit_of_pixel[p] = static_cast<int32_t>(k);
  // Every ray's hit by plain traversal (nothing else of it is used), on every core when there
  // are several.
  HitBackend host(image);
  std::optional<ParallelBackend> parallel;
  if (parallel_threads() > 1) parallel.emplace(host);
  TraceBackend& plain = parallel ? static_cast<TraceBackend&>(*parallel) : host;
  const bool warm = params_.warmup == SampleWarmup::kFunctional;
  GenerationSampler sampler(plain, tier, std::move(unit_of_pixel), static_cast<int>(units.size()),
                            warm ? params_.warmup_rays : 0);
  frame = WhittedTracer(scene, tracer, sampler).render(camera, width_, height_);
  // Figures in this round's order, the same for every layout (every unit has a primary ray
  // per pixel, so every unit has every key).
  for (size_t k = 0; k < units.size(); ++k) {
    for (const auto& [key, value] : sampler.unit_values()[k]) sample.values[key].push_back(value);
    sample.unit_rays.push_back(sampler.unit_rays()[k]);
    if (&sample == &layouts_.front()) strata_taken_.push_back(plan_.stratum[units[k]]);
  }
  sample.frame_rays = double(frame.rays_total());
  sample.rays_simulated += sampler.rays_measured();
  sample.rays_warmed += sampler.rays_warmed();
}

void SampledFrame::trace_units(WhittedTracer& tracer, const PinholeCamera& camera,
                               const TierRun& tier, size_t from, size_t to,
                               FrameResult& frame, LayoutSample& sample) {
  // This round's units in scan order of their first pixel, so warming runs forwards.
  const std::vector<uint32_t> units = round_units(from, to);
  const bool warm = params_.warmup == SampleWarmup::kFunctional && params_.warmup_pixels > 0;
  FrameResult scratch;  // the warming pixels' rays: not measured
  if (warm) scratch = tracer.begin_frame(camera, width_, height_);
  std::map<std::string, double> unit_values;
  Stats before, after;
  uint32_t last_traced = UINT32_MAX;
  std::vector<uint32_t> warm_pixels;

  // Traces `pixels` (adjacent in scan order when warming) and adds what they did to the unit.
  auto measure = [&](std::span<const uint32_t> pixels) {
    if (warm && pixels.front() != last_traced + 1) {
      warm_pixels.clear();
      const uint32_t first = pixels.front();
      for (uint32_t p = first - std::min<uint32_t>(first, params_.warmup_pixels); p < first; ++p)
        warm_pixels.push_back(p);
      tracer.render_pixels(camera, warm_pixels, scratch);
    }
    const auto rays_before = frame.rays_by_kind;
    tier.write_stats(before);
    tracer.render_pixels(camera, pixels, frame);
    tier.write_stats(after);
    add_extensive_change(before, after, unit_values);
    uint64_t rays = 0;
    for (int k = 0; k < kRayKinds; ++k) {
      unit_values[kRayKeys[k]] += double(frame.rays_by_kind[k] - rays_before[k]);
      rays += frame.rays_by_kind[k] - rays_before[k];
    }
    unit_values["rays.total"] += double(rays);
    sample.rays_simulated += rays;
    last_traced = pixels.back();
  };

  for (const uint32_t u : units) {
    const std::vector<uint32_t>& pixels = plan_.units[u];
    unit_values.clear();
    if (!warm) {
      measure(pixels);
    } else {
      // Each run of adjacent pixels is warmed and measured on its own.
      size_t start = 0;
      for (size_t i = 1; i <= pixels.size(); ++i)
        if (i == pixels.size() || pixels[i] != pixels[i - 1] + 1) {
          measure(std::span<const uint32_t>(pixels).subspan(start, i - start));
          start = i;
        }
    }
    // Figures in this round's trace order, the same for every layout.
    for (const auto& [key, value] : unit_values) sample.values[key].push_back(value);
    if (&sample == &layouts_.front()) strata_taken_.push_back(plan_.stratum[u]);
  }
}

Estimate SampledFrame::estimate(const LayoutSample& sample,
                                const std::vector<double>& values) const {
  if (params_.estimator == SampleEstimator::kRatio)
    return estimator_.ratio(values, sample.unit_rays, sample.frame_rays, strata_taken_);
  return estimator_.total(values, strata_taken_);
}

Estimate SampledFrame::figure(const LayoutSample& sample, const std::string& key) const {
  const std::vector<double>& values = sample.values.at(key);
  if (order_ == RayOrder::kWavefront || (key != "rays.primary" && key != "rays.total"))
    return estimate(sample, values);
  const double pixels = double(width_) * height_;
  if (key == "rays.primary") return Estimate{.value = pixels};
  const std::vector<double>& primary = sample.values.at("rays.primary");
  std::vector<double> others(values.size());
  for (size_t i = 0; i < values.size(); ++i) others[i] = values[i] - primary[i];
  Estimate e = estimate(sample, others);
  e.value += pixels;
  return e;
}

std::pair<double, std::string> SampledFrame::widest_ci(const LayoutSample& sample) const {
  // In wavefront order rays.* are counted exactly, and rays.primary in any order: a target on
  // one is met with no width.
  if ((order_ == RayOrder::kWavefront && is_ray_key(params_.target_key)) ||
      params_.target_key == "rays.primary")
    return {0.0, params_.target_key};
  std::pair<double, std::string> widest{0.0, ""};
  for (const auto& [key, values] : sample.values) {
    if (!params_.target_key.empty() && key != params_.target_key) continue;
    const double w = figure(sample, key).relative_half_width();
    if (w > widest.first || widest.second.empty()) widest = {w, key};
  }
  return widest;
}

FrameResult SampledFrame::render(const Scene& scene, const TracerParams& tracer_params,
                                 const PinholeCamera& camera, TierRun& tier,
                                 const MemoryImage& image, const std::string& layout,
                                 double& seconds) {
  const auto t0 = std::chrono::steady_clock::now();
  layouts_.push_back(LayoutSample{.layout = layout});
  LayoutSample& sample = layouts_.back();
  WhittedTracer tracer(scene, tracer_params, tier.backend());
  FrameResult frame = tracer.begin_frame(camera, width_, height_);
  // One round: units [from, to) of the drawing order.
  auto trace_round = [&](size_t from, size_t to) {
    if (order_ == RayOrder::kWavefront)
      trace_generations(scene, tracer_params, camera, tier, image, from, to, frame, sample);
    else
      trace_units(tracer, camera, tier, from, to, frame, sample);
  };
  if (layouts_.size() == 1) {
    // The first layout draws the units: the rate's share, or rounds until the target CI.
    const size_t cap = std::max<size_t>(1, std::llround(params_.rate * double(plan_.size())));
    size_t n = cap;
    if (params_.target_ci > 0.0)
      n = std::min(cap, std::max<size_t>(params_.min_units, 2 * plan_.stratum_units.size()));
    trace_round(0, n);
    rounds_.push_back(n);
    // In wavefront order rays.* are counted exactly: a target on them is met at once.
    const bool exact_key = order_ == RayOrder::kWavefront && is_ray_key(params_.target_key);
    if (!params_.target_key.empty() && !exact_key && !sample.values.count(params_.target_key))
      throw InputError(params_.target_key_origin + ": sample.target_key: '" + params_.target_key +
                       "' is not measured by this tier");
    while (params_.target_ci > 0.0 && n < cap) {
      const double w = widest_ci(sample).first;
      if (w <= params_.target_ci) break;
      // The half-width goes as sqrt((1 - n/N) / n) (the finite-population correction: without
      // it rounds overshot by about 2x): aim 10% past the units that should reach it.
      double wanted = 2.0 * double(n);
      if (std::isfinite(w)) {
        const double big_n = double(plan_.size());
        const double q = (1.0 - double(n) / big_n) / double(n) *
                         (params_.target_ci / w) * (params_.target_ci / w);
        wanted = 1.1 / (q + 1.0 / big_n);
      }
      const size_t next = std::min(cap, std::max(n + 1, size_t(std::ceil(wanted))));
      trace_round(n, next);
      rounds_.push_back(n = next);
    }
  } else {
    // Later layouts: the same units in the same rounds.
    size_t from = 0;
    for (const size_t to : rounds_) {
      trace_round(from, to);
      from = to;
    }
  }
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  sample.seconds = seconds;
  return frame;
}

void SampledFrame::finish_layout(FrameResult& frame, Stats& stats) const {
  const LayoutSample& sample = layouts_.back();
  const Stats measured = stats;  // the tier's own counts: the measured and the warming rays'
  for (const auto& [key, values] : sample.values) {
    const Estimate e = figure(sample, key);
    stats.set(key, e.value);
    // Every figure here is a count, never below zero: so is its interval (a paired difference's
    // below may be negative).
    stats.set(key + ".ci95_low", std::max(0.0, e.ci_low()));
    stats.set(key + ".ci95_high", e.ci_high());
  }
  if (order_ == RayOrder::kWavefront) {
    stats.set("sample.rays_warmed", sample.rays_warmed);
    // Per generation the whole frame is traced: its ray counts are exact, not estimates.
    for (int k = 0; k <= kRayKinds; ++k) {
      const std::string key = k < kRayKinds ? kRayKeys[k] : "rays.total";
      const double rays = double(k < kRayKinds ? frame.rays_by_kind[k] : frame.rays_total());
      stats.set(key, rays);
      stats.set(key + ".ci95_low", rays);
      stats.set(key + ".ci95_high", rays);
    }
  } else {
    // rays.primary is the pixel count (units of unequal size made a zero-width CI that missed
    // it), rays.total that plus the other rays' estimate (figure()).
    for (int k = 0; k < kRayKinds; ++k)
      frame.rays_by_kind[k] =
          static_cast<uint64_t>(std::llround(figure(sample, kRayKeys[k]).value));
  }
  // Figures derived from counts, from the estimated counts: a rate over simulated time scales
  // with its count and inversely with the cycles; the shares are ratios of estimates.
  const auto number = [](const Stats& s, const std::string& key) {
    return s.has(key) && s.at(key).is_number() ? s.at(key).get<double>() : 0.0;
  };
  const auto rescale = [&](const char* rate, const char* count) {
    const double c0 = number(measured, count), y0 = number(measured, "sim.cycles");
    const double c1 = number(stats, count), y1 = number(stats, "sim.cycles");
    if (stats.has(rate) && c0 > 0 && y0 > 0 && y1 > 0)
      stats.set(rate, number(measured, rate) * (c1 / c0) * (y0 / y1));
  };
  rescale("sim.rays_per_second", "unit.rays");
  rescale("dram.gbytes_per_second", "dram.bytes.total");
  if (stats.has("dram.row_hit_rate")) {
    const double rows = number(stats, "dram.row_hits") + number(stats, "dram.row_misses") +
                        number(stats, "dram.row_conflicts");
    stats.set("dram.row_hit_rate", rows > 0 ? number(stats, "dram.row_hits") / rows : 0.0);
  }
  if (stats.has("unit.utilisation") && number(stats, "sim.cycles") > 0)
    stats.set("unit.utilisation", number(stats, "unit.steps") / number(stats, "sim.cycles"));
  const auto [w, key] = widest_ci(sample);
  stats.set("sample.achieved_ci", w);
  stats.set("sample.achieved_ci_key", key);
  stats.set("sample.rays_simulated", sample.rays_simulated);
  stats.set("sample.rays_simulated_per_second",
            sample.seconds > 0 ? double(sample.rays_simulated) / sample.seconds : 0.0);
}

void SampledFrame::write_run_stats(Stats& stats) const {
  const size_t n = rounds_.empty() ? 0 : rounds_.back();
  size_t pixels = 0;
  for (size_t i = 0; i < n; ++i) pixels += plan_.units[plan_.order[i]].size();
  stats.set("sample.method", params_.method_name);
  stats.set("sample.rate", params_.rate);
  stats.set("sample.seed", params_.seed);
  stats.set("sample.warmup", params_.warmup_name);
  stats.set("sample.estimator", params_.estimator_name);
  stats.set("sample.target_ci", params_.target_ci);
  stats.set("sample.units", n);
  stats.set("sample.units_total", plan_.size());
  stats.set("sample.rounds", rounds_.size());
  stats.set("sample.pixels", pixels);
  stats.set("sample.fraction", double(pixels) / (double(width_) * height_));
  const Estimate any = estimator_.total(std::vector<double>(n, 0.0), strata_taken_);
  stats.set("sample.ci_valid", any.valid);
  stats.set("sample.problem", any.problem);
  if (params_.target_ci > 0.0)
    stats.set("sample.target_met", widest_ci(layouts_.front()).first <= params_.target_ci);
  if (!any.valid)
    std::fprintf(stderr, "rtusim: sample: %s: the 95%% confidence intervals are not valid\n",
                 any.problem.c_str());
  // Wavefront order: the whole frame traced per generation, the units measured within it.
  stats.set("sample.per_generation", order_ == RayOrder::kWavefront);

  // Paired differences: layout b minus layout a over the same units.
  for (size_t a = 0; a < layouts_.size(); ++a)
    for (size_t b = a + 1; b < layouts_.size(); ++b)
      for (const char* key : kPairedKeys) {
        const auto ia = layouts_[a].values.find(key), ib = layouts_[b].values.find(key);
        if (ia == layouts_[a].values.end() || ib == layouts_[b].values.end()) continue;
        std::vector<double> d(ia->second.size());
        for (size_t i = 0; i < d.size(); ++i) d[i] = ib->second[i] - ia->second[i];
        const Estimate e = estimate(layouts_[a], d);  // the units' rays: the same in b
        const std::string stem =
            "sample.diff." + layouts_[b].layout + "-" + layouts_[a].layout + "." + key;
        stats.set(stem, e.value);
        stats.set(stem + ".ci95_low", e.ci_low());
        stats.set(stem + ".ci95_high", e.ci_high());
      }
}

}  // namespace rtusim
