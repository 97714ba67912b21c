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
  // functional.timed_segments: the timed mode cuts a batch into up to this many runs of rays,
  // each timed by its own model on any thread (TimedInterleaver); 1: one model, serial.
  int timed_segments = 1;
  // functional.timed_warmup_rays: the rays before each run timed unmeasured to warm it.
  int timed_warmup_rays = 256;

  // Not the plain tier: the rays' fetches interleave (round-robin or timed), so the node stream
  // is not the one-ray-at-a-time stream that trace records and a sweep's one pass evaluates.
  bool interleaved() const { return rays_in_flight > 1 || timed; }
};

// Reads functional.*.
FunctionalParams read_functional_params(ConfigReader& r);

}  // namespace rtusim
