// `rtusim run`: one simulation; stats.json, the effective config and the image.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "app/commands.h"
#include "app/pipeline.h"
#include "image/png_writer.h"
#include "tracer/host_backend.h"
#include "tracer/whitted_tracer.h"
#include "util/output_files.h"
#include "util/stats.h"

namespace rtusim {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void add_tree_stats(const KdTree& tree, const Scene& scene, Stats& s) {
  const KdTreeReport& r = tree.report;
  s.set("scene.triangles", scene.triangle_count());
  s.set("scene.materials", scene.materials.size());
  s.set("scene.lights", scene.lights.size());
  s.set("scene.bytes", scene.geometry_bytes());
  s.set("tree.nodes", r.nodes);
  s.set("tree.leaves", r.leaves);
  s.set("tree.empty_leaves", r.empty_leaves);
  s.set("tree.max_depth", r.max_depth);
  s.set("tree.mean_leaf_depth", r.mean_leaf_depth);
  s.set("tree.refs_per_triangle", r.refs_per_triangle);
  s.set("tree.sah_cost", r.sah_cost);
  s.set("tree.build_seconds", r.build_seconds);
  s.set("tree.build_peak_bytes", r.peak_build_bytes);
}

}  // namespace

int run_command(const RunOptions& opts) {
  const auto t_start = std::chrono::steady_clock::now();
  const std::string out_dir = opts.out.empty() ? "out" : opts.out;
  const Prepared p = prepare_run(opts.config, opts.overrides);
  OutputFiles outputs(out_dir);  // created only once the inputs are known to be good

  // Trace the frame over the first layout's image (hits are the same for every layout).
  const MemoryImage& image = p.images.front();
  HostBackend backend(image);
  WhittedTracer tracer(p.scene, p.config.tracer, backend);
  const PinholeCamera camera(p.camera, p.config.image.width, p.config.image.height);
  const auto t_trace = std::chrono::steady_clock::now();
  const FrameResult frame = tracer.render(camera, p.config.image.width, p.config.image.height);
  const double trace_seconds = seconds_since(t_trace);

  Stats s;
  add_tree_stats(p.tree, p.scene, s);
  s.set("rays.total", frame.rays_total());
  s.set("rays.primary", frame.rays_by_kind[int(RayKind::kPrimary)]);
  s.set("rays.shadow", frame.rays_by_kind[int(RayKind::kShadow)]);
  s.set("rays.reflection", frame.rays_by_kind[int(RayKind::kReflection)]);
  s.set("rays.refraction", frame.rays_by_kind[int(RayKind::kRefraction)]);
  s.set("layout.kind", image.layout);
  s.set("tree.bytes", image.nodes.size_bytes);
  s.set("mem.nodes.bytes", image.nodes.size_bytes);
  s.set("mem.lists.bytes", image.lists.size_bytes);
  s.set("mem.triangles.bytes", image.triangles.size_bytes);
  s.set("mem.image.bytes", image.bytes.size());
  const FetchCounts& c = backend.counts();
  s.set("traversal.node_fetches", c.fetches[int(Stream::kNode)]);
  s.set("traversal.list_fetches", c.fetches[int(Stream::kList)]);
  s.set("traversal.triangle_fetches", c.fetches[int(Stream::kTriangle)]);
  s.set("traversal.node_bytes", c.bytes[int(Stream::kNode)]);
  s.set("traversal.list_bytes", c.bytes[int(Stream::kList)]);
  s.set("traversal.triangle_bytes", c.bytes[int(Stream::kTriangle)]);
  s.set("sim.tier", "host");
  s.set("scene.load_seconds", p.scene_load_seconds);
  s.set("trace.seconds", trace_seconds);
  s.set("trace.rays_per_second", trace_seconds > 0 ? frame.rays_total() / trace_seconds : 0.0);

  // Outputs: effective config, image, then stats (run.seconds last).
  std::ostringstream cfg;
  cfg << "# Effective config of " << p.config.origin << " (defaults and --set applied)\n"
      << p.config.effective << "\n";
  outputs.write_text("config.toml", cfg.str());
  if (p.config.image.write_png)
    write_png(outputs.stage("image.png").string(), frame.width, frame.height,
              to_srgb8(frame.radiance));
  s.set("run.seconds", seconds_since(t_start));
  outputs.write_text("stats.json", s.to_json().dump(2) + "\n");
  outputs.commit();

  // Summary table.
  std::printf("rtusim run %s -> %s\n", opts.config.c_str(), out_dir.c_str());
  std::printf("  scene     %-40s %10u triangles\n", p.scene.source.c_str(),
              p.scene.triangle_count());
  std::printf("  kd-tree   %10llu nodes  %8llu leaves  depth %u  SAH %.2f  built in %.3f s\n",
              (unsigned long long)p.tree.report.nodes, (unsigned long long)p.tree.report.leaves,
              p.tree.report.max_depth, p.tree.report.sah_cost, p.tree.report.build_seconds);
  std::printf("  rays      %10llu total: %llu primary, %llu shadow, %llu reflection, %llu refraction\n",
              (unsigned long long)frame.rays_total(),
              (unsigned long long)frame.rays_by_kind[0], (unsigned long long)frame.rays_by_kind[1],
              (unsigned long long)frame.rays_by_kind[2], (unsigned long long)frame.rays_by_kind[3]);
  std::printf("  %-9s %10s %14s %14s %16s\n", "layout", "node bytes", "node fetches",
              "fetches/ray", "node bytes/ray");
  std::printf("  %-9s %10llu %14llu %14.2f %16.1f\n", image.layout.c_str(),
              (unsigned long long)image.nodes.size_bytes,
              (unsigned long long)c.fetches[int(Stream::kNode)],
              double(c.fetches[int(Stream::kNode)]) / std::max<uint64_t>(1, frame.rays_total()),
              double(c.bytes[int(Stream::kNode)]) / std::max<uint64_t>(1, frame.rays_total()));
  std::printf("  traced in %.3f s (%.2f Mrays/s, host traversal, 1 thread)\n", trace_seconds,
              frame.rays_total() / std::max(trace_seconds, 1e-9) / 1e6);
  return 0;
}

}  // namespace rtusim
