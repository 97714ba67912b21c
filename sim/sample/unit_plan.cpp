#include "sample/unit_plan.h"

#include <algorithm>
#include <random>

namespace rtusim {
namespace {

// Fisher-Yates with the engine's raw output, so the order is the same with every standard
// library (std::shuffle's algorithm is unspecified).
template <class T>
void shuffle(std::vector<T>& v, std::mt19937_64& rng) {
  for (size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[rng() % i]);
}

// Splits `pixels` (already in random order) into units of `per_unit`, each sorted to scan order.
void add_random_units(std::vector<uint32_t>& pixels, int per_unit, int stratum, UnitPlan& plan) {
  for (size_t i = 0; i < pixels.size(); i += per_unit) {
    std::vector<uint32_t> unit(pixels.begin() + i,
                               pixels.begin() + std::min(pixels.size(), i + per_unit));
    std::sort(unit.begin(), unit.end());
    plan.units.push_back(std::move(unit));
    plan.stratum.push_back(stratum);
  }
}

}  // namespace

UnitPlan make_unit_plan(const SampleParams& params, int width, int height) {
  UnitPlan plan;
  std::mt19937_64 rng(params.seed);
  const int g = params.unit_pixels;
  // Strata: the blocks of a k x k grid (k = 1 for random).
  const int k = params.method == SampleMethod::kRandom
                    ? 1
                    : std::max(1, std::min({params.strata, width, height}));
  if (params.method == SampleMethod::kTiles) {
    // Row segments: adjacent in the full frame's scan order, so a unit keeps its coherence; a
    // segment's stratum is the block of its first pixel.
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; x += g) {
        std::vector<uint32_t> unit;
        for (int i = x; i < std::min(width, x + g); ++i) unit.push_back(uint32_t(y) * width + i);
        plan.units.push_back(std::move(unit));
        plan.stratum.push_back(int64_t(y) * k / height * k + int64_t(x) * k / width);
      }
  } else {
    // Each block's pixels split at random into units.
    for (int by = 0; by < k; ++by)
      for (int bx = 0; bx < k; ++bx) {
        std::vector<uint32_t> pixels;
        for (int y = by * height / k; y < (by + 1) * height / k; ++y)
          for (int x = bx * width / k; x < (bx + 1) * width / k; ++x)
            pixels.push_back(uint32_t(y) * width + x);
        shuffle(pixels, rng);
        add_random_units(pixels, g, by * k + bx, plan);
      }
  }
  // Strata numbered densely, empty blocks (narrow frames, long segments) left out.
  std::vector<int> dense(size_t(k) * k, -1);
  int strata = 0;
  for (int& s : plan.stratum) {
    if (dense[s] < 0) dense[s] = strata++;
    s = dense[s];
  }
  plan.stratum_units.assign(strata, 0.0);
  for (int s : plan.stratum) plan.stratum_units[s] += 1.0;

  // Drawing order: a random order within each stratum; the strata interleaved in proportion by
  // sorting on (rank + offset) / size, with a random offset per stratum.
  std::vector<std::vector<uint32_t>> by_stratum(strata);
  for (uint32_t u = 0; u < plan.units.size(); ++u) by_stratum[plan.stratum[u]].push_back(u);
  std::vector<std::pair<double, uint32_t>> keyed;
  std::uniform_real_distribution<double> offset(0.0, 1.0);
  for (auto& members : by_stratum) {
    shuffle(members, rng);
    const double o = offset(rng);
    for (size_t r = 0; r < members.size(); ++r)
      keyed.push_back({(double(r) + o) / double(members.size()), members[r]});
  }
  std::sort(keyed.begin(), keyed.end());
  for (const auto& [key, u] : keyed) plan.order.push_back(u);
  return plan;
}

}  // namespace rtusim
