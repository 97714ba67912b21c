// Timing helpers shared by the benchmarks: wall-clock seconds and medians of repeated runs.
#pragma once
#include <algorithm>
#include <chrono>
#include <vector>

namespace rtusim::bench_timing {

inline double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The median wall time of `reps` calls of `run`.
template <class F>
double median_seconds(int reps, F&& run) {
  std::vector<double> s;
  for (int i = 0; i < reps; ++i) {
    const double t0 = now_s();
    run();
    s.push_back(now_s() - t0);
  }
  return median(s);
}

}  // namespace rtusim::bench_timing
