// Timing helpers shared by the benchmarks: wall-clock and thread CPU seconds, medians of
// repeated runs, and the one-line result format that bench/run_all.py collects.
#pragma once
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

namespace rtusim::bench_timing {

inline double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// CPU seconds of the calling thread: what one core spends on the work, unaffected by other
// processes taking turns on a shared machine (wall time is, by up to several times).
inline double cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The median of `reps` calls of `run`, timed by `clock` (seconds).
template <class Clock, class F>
double median_timed(int reps, Clock clock, F&& run) {
  std::vector<double> s;
  for (int i = 0; i < reps; ++i) {
    const double t0 = clock();
    run();
    s.push_back(clock() - t0);
  }
  return median(s);
}

// The median wall time of `reps` calls of `run`.
template <class F>
double median_seconds(int reps, F&& run) {
  return median_timed(reps, now_s, run);
}

// The median CPU time of the calling thread over `reps` calls of `run`.
template <class F>
double median_cpu_seconds(int reps, F&& run) {
  return median_timed(reps, cpu_s, run);
}

// A result line for bench/run_all.py: `RATIO<TAB>bench<TAB>case<TAB>subject<TAB>value<TAB>
// reference<TAB>reference value<TAB>unit<TAB>ratio`, where ratio = value / reference value and
// both values were measured in the same run (medians).
inline void print_ratio(const char* bench, const char* case_name, const char* subject,
                        double value, const char* reference, double reference_value,
                        const char* unit) {
  std::printf("RATIO\t%s\t%s\t%s\t%.4g\t%s\t%.4g\t%s\t%.3f\n", bench, case_name, subject,
              value, reference, reference_value, unit, value / reference_value);
}

}  // namespace rtusim::bench_timing
