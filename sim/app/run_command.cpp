// `rtusim run`: one simulation; stats.json, the effective config, the image and heatmaps.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "app/commands.h"
#include "app/simulation.h"
#include "image/heatmap.h"
#include "image/png_writer.h"
#include "tracer/parallel_render.h"
#include "util/output_files.h"
#include "util/stat_decl.h"

namespace rtusim {
namespace {
// Stats keys of `rtusim run` itself.
const StatDecl kRunSeconds("run.seconds", StatKind::kTiming, "s",
                           "wall time of the whole run");

void print_summary(const RunOptions& opts, const std::string& out_dir, const Prepared& p,
                   const SimulationResult& r) {
  const KdTreeReport& t = p.tree.report;
  const FrameResult& f = r.frame;
  std::printf("rtusim run %s -> %s\n", opts.config.c_str(), out_dir.c_str());
  std::printf("  scene    %s: %u triangles, %dx%d, tier %s\n", p.scene.source.c_str(),
              p.scene.triangle_count(), f.width, f.height, p.config.sim.tier.c_str());
  std::printf("  kd-tree  %llu nodes, %llu leaves, depth %u, SAH %.1f, built in %.3f s\n",
              (unsigned long long)t.nodes, (unsigned long long)t.leaves, t.max_depth, t.sah_cost,
              t.build_seconds);
  std::printf("  rays     %llu: %llu primary, %llu shadow, %llu reflection, %llu refraction\n",
              (unsigned long long)f.rays_total(), (unsigned long long)f.rays_by_kind[0],
              (unsigned long long)f.rays_by_kind[1], (unsigned long long)f.rays_by_kind[2],
              (unsigned long long)f.rays_by_kind[3]);
  const CacheParams& l1 = p.config.l1.params.cache;
  std::printf("  node L1  %llu B, %u-way, %u B lines, %s; GB/s at %.0f frames/s\n",
              (unsigned long long)l1.size_bytes, l1.assoc, l1.line_bytes, l1.policy.c_str(),
              p.config.report.frames_per_second);
  const ChipParams& chip = p.config.chip;
  if (!chip.single_unit()) {
    std::printf("  chip     %u unit%s (%s)", chip.units, chip.units > 1 ? "s" : "",
                chip.distribution == RayDistribution::kTiles
                    ? ("tiles of " + std::to_string(chip.tile_pixels) + "x" +
                       std::to_string(chip.tile_pixels) + " pixels")
                          .c_str()
                    : ("runs of " + std::to_string(chip.batch_rays) + " rays").c_str());
    if (chip.l2)
      std::printf(", shared L2 %llu B, %u-way, %u B lines, %s", (unsigned long long)chip.l2->size_bytes,
                  chip.l2->assoc, chip.l2->line_bytes, chip.l2->policy.c_str());
    std::printf("\n");
  }
  const bool l2 = r.stats.has("l2.accesses");  // all streams: L1s -> L2 -> DRAM
  const bool timed = r.stats.has("sim.cycles");  // a tier that keeps time
  int name_width = 8;  // the layout column: as wide as its longest name (subtree-bfs: 11)
  for (const LayoutRun& run : r.layouts)
    name_width = std::max(name_width, static_cast<int>(run.kind.size()));
  std::printf("  %-*s %12s %12s %10s %11s %9s %9s", name_width, "layout", "node memory", "L1 misses",
              "miss rate", "node B/ray", "node MB", "node GB/s");
  if (l2) std::printf(" %11s %8s %9s", "L1->L2 GB/s", "L2 miss", "DRAM GB/s");
  if (timed) std::printf(" %12s %9s %8s", "cycles", "DRAM GB/s", "Mrays/s");
  std::printf("\n");
  for (const LayoutRun& run : r.layouts) {
    const Stats& s = run.stats;
    std::printf("  %-*s %12llu %12llu %9.2f%% %11.1f %9.2f %9.3f", name_width, run.kind.c_str(),
                s.at("tree.bytes").get<unsigned long long>(),
                s.at("l1.misses").get<unsigned long long>(),
                100.0 * s.at("l1.miss_rate").get<double>(),
                s.at("report.node_dram_bytes_per_ray").get<double>(),
                s.at("dram.bytes.nodes").get<double>() / 1e6,
                s.at("report.node_gbytes_per_second").get<double>());
    if (l2) {
      const double fps = p.config.report.frames_per_second;
      std::printf(" %11.3f %7.2f%% %9.3f", s.at("l2.bytes.in").get<double>() * fps / 1e9,
                  100.0 * s.at("l2.miss_rate").get<double>(),
                  s.at("dram.bytes.total").get<double>() * fps / 1e9);
    }
    if (timed)
      std::printf(" %12llu %9.2f %8.1f", s.at("sim.cycles").get<unsigned long long>(),
                  s.at("dram.gbytes_per_second").get<double>(),
                  s.at("sim.rays_per_second").get<double>() / 1e6);
    std::printf("\n");
  }
  const double secs = r.layouts.front().stats.at("trace.seconds").get<double>();
  std::printf("  simulated in %.3f s per layout (%.2f Mrays/s of wall time, %s tier, --threads %d)%s\n",
              secs, f.rays_total() / std::max(secs, 1e-9) / 1e6, p.config.sim.tier.c_str(),
              parallel_threads(),
              timed ? "; node GB/s at the frame rate, DRAM GB/s and Mrays/s at the unit's clock"
              : l2  ? "; GB/s at the frame rate, node columns after the L2, L1->L2 and DRAM all streams"
                    : "");
}

}  // namespace

int run_command(const RunOptions& opts) {
  const auto t_start = std::chrono::steady_clock::now();
  const std::string out_dir = opts.out.empty() ? "out" : opts.out;
  const Prepared p = prepare_run(opts.config, opts.overrides);
  if (p.config.sim.tier == "functional" && !p.config.sim.vcd_path.empty())
    std::fprintf(stderr, "rtusim: note: sim.vcd (%s) is not written: the functional tier has no "
                 "signals (sim.tier = cycle or rtl writes it)\n", p.config.sim.vcd_path.c_str());
  OutputFiles outputs(out_dir);  // created only once the inputs are known to be good
  // An earlier run's pictures that this run does not draw go: the directory shows this run.
  outputs.replace_earlier([](const std::string& n) {
    return n.ends_with(".png") &&
           (n == "image.png" || n.starts_with("heatmap_") || n.starts_with("diff_"));
  });
  SimulationResult r = simulate(p);

  // Outputs: effective config, image, heatmaps, then stats (run.seconds last).
  std::ostringstream cfg;
  // A relative scene path made absolute, so the file runs again from any directory.
  toml::table effective = p.config.effective;
  const std::string& scene = p.config.scene.path;
  if (auto* path = effective["scene"]["path"].as_string();
      path && !scene.starts_with("builtin:") && !scene.starts_with("$") &&
      !std::filesystem::path(scene).is_absolute())
    *path = std::filesystem::absolute(p.config.scene.resolved).lexically_normal().string();
  cfg << "# Effective config of " << p.config.origin << " (defaults and --set applied)\n"
      << effective << "\n";
  outputs.write_text("config.toml", cfg.str());
  const int w = r.frame.width, h = r.frame.height;
  if (p.config.image.write_png)
    write_png(outputs.stage("image.png").string(), w, h, to_srgb8(r.frame.radiance));
  // Heatmaps need each ray's traffic, which only the functional tier attributes to pixels.
  if (p.config.image.heatmaps && !r.layouts.front().pixel_dram_bytes.empty()) {
    uint64_t max_bytes = 1;
    for (const LayoutRun& run : r.layouts)
      for (uint64_t b : run.pixel_dram_bytes) max_bytes = std::max(max_bytes, b);
    for (const LayoutRun& run : r.layouts) {
      const Rgb8Image map = heatmap_with_scale_rgb8(run.pixel_dram_bytes, w, h, max_bytes);
      write_png(outputs.stage("heatmap_" + run.kind + ".png").string(), map.width, map.height,
                map.rgb);
    }
    const auto find = [&](const std::string& k) -> const LayoutRun* {
      for (const LayoutRun& run : r.layouts)
        if (run.kind == k) return &run;
      return nullptr;
    };
    if (const LayoutRun *dfl = find("dfl"), *odfl = find("odfl"); dfl && odfl)
      write_png(outputs.stage("diff_odfl_dfl.png").string(), w, h,
                difference_rgb8(dfl->pixel_dram_bytes, odfl->pixel_dram_bytes));
  }
  r.stats.set("run.seconds",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count());
  outputs.write_text("stats.json", r.stats.to_json().dump(2) + "\n");
  outputs.commit();
  print_summary(opts, out_dir, p, r);
  return 0;
}

}  // namespace rtusim
