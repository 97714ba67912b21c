// One simulation over a prepared run: the frame traced once per layout through the configured
// tier, with the stats of every layout. Shared by `rtusim run` and `rtusim regress`.
#pragma once
#include <string>
#include <vector>

#include "app/pipeline.h"
#include "tracer/whitted_tracer.h"
#include "util/stats.h"

namespace rtusim {

struct LayoutRun {
  std::string kind;
  Stats stats;                             // this layout's keys (tree.bytes, l1.*, dram.* ...)
  std::vector<uint64_t> pixel_dram_bytes;  // DRAM bytes of each pixel's ray tree
};

struct SimulationResult {
  FrameResult frame;
  std::vector<LayoutRun> layouts;  // in layout.kind order
  // Everything for stats.json but run.seconds: run-wide keys, the first layout's keys, and
  // with several layouts every layout's keys again under "layout.<kind>.".
  Stats stats;
};

SimulationResult simulate(const Prepared& p);

// The stats simulate() writes besides the tier's, for whoever counts a run another way (sweeps).
// Run-wide keys: scene.*, tree.*, rays.*, sim.tier, report.frames_per_second.
void add_run_stats(const Prepared& p, const FrameResult& frame, Stats& s);
// Keys of a layout's memory image: layout.kind, tree.bytes, mem.*.bytes.
void add_image_stats(const MemoryImage& image, Stats& s);
// Figures derived from a tier's counters (l1.miss_rate, report.*), the same for every tier, and
// the trace timing of `seconds`.
void add_report_stats(const FrameResult& frame, double fps, double seconds, Stats& s);

}  // namespace rtusim
