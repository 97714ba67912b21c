// The sampling units of a frame and the order they are drawn in: the frame's pixels split into
// units (a row segment, or pixels drawn at random from the frame or from a stratum), and a
// seeded order such that every prefix is a simple random sample of units without replacement
// in each stratum, the strata in proportion to their sizes.
#pragma once
#include <cstdint>
#include <vector>

#include "sample/sample_params.h"

namespace rtusim {

struct UnitPlan {
  std::vector<std::vector<uint32_t>> units;  // each unit's pixels (row-major index), scan order
  std::vector<int> stratum;                  // each unit's stratum
  std::vector<double> stratum_units;         // units in each stratum (the population sizes)
  std::vector<uint32_t> order;               // unit indices in drawing order

  size_t size() const { return units.size(); }
};

UnitPlan make_unit_plan(const SampleParams& params, int width, int height);

}  // namespace rtusim
