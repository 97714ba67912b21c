// The functional tier's keys (functional.*, declared in functional_tier.cpp).
#pragma once

namespace rtusim {

class ConfigReader;

struct FunctionalParams {
  // functional.rays_in_flight: rays in traversal at once. 1 is the plain functional tier (each
  // ray traversed to the end in turn); more is the interleaved mode (FunctionalBackend).
  int rays_in_flight = 1;
  // functional.timed: the rays in flight take turns by a cheap model of the cycle tier's timing
  // (TimedInterleaver, its params the cycle tier's keys), not round-robin; estimates cycles.
  bool timed = false;
};

// Reads functional.*.
FunctionalParams read_functional_params(ConfigReader& r);

}  // namespace rtusim
