// rtusim command-line entry point: subcommands, and the exit-status contract
// (0 success, 2 bad input with one line on stderr, 1 internal error).
#include <iostream>
#include <optional>

#include <CLI/CLI.hpp>
#include <oneapi/tbb/global_control.h>

#include "app/commands.h"
#include "app/set_option.h"
#include "app/thread_count_option.h"
#include "util/error.h"
#include "util/output_files.h"

int main(int argc, char** argv) {
  using namespace rtusim;
  CLI::App app{"rtusim: cycle-approximate simulator of a kd-tree ray-tracing unit"};
  app.require_subcommand(1);
  RunOptions run_opts, hits_opts;
  // --threads N of run, hits and trace: never changes a result (tracer/parallel_render.h).
  int threads = 0;
  auto add_threads = [&](CLI::App* sub) {
    sub->add_option("--threads", threads, "Tracing threads (default: all cores; 1: one thread)")
        ->check(thread_count());
  };

  auto* run = app.add_subcommand("run", "Run one simulation: stats.json, config.toml, image.png");
  run->add_option("config", run_opts.config, "TOML run config")->required();
  add_set_option(run, run_opts.overrides, "Override a config key");
  run->add_option("--out", run_opts.out, "Output directory (default: out)");
  add_threads(run);

  auto* hits = app.add_subcommand("hits", "Write primary-ray hits (RTH1 format)");
  hits->add_option("config", hits_opts.config, "TOML run config")->required();
  add_set_option(hits, hits_opts.overrides, "Override a config key");
  hits->add_option("--out", hits_opts.out, "Output file")->required();
  add_threads(hits);

  TraceOptions trace_opts;
  auto* trace =
      app.add_subcommand("trace", "Write the node-fetch address stream (din, din-sized or bin)");
  trace->add_option("config", trace_opts.config, "TOML run config (one layout)")->required();
  add_set_option(trace, trace_opts.overrides, "Override a config key");
  trace->add_option("--out", trace_opts.out, "Output trace file")->required();
  trace->add_option("--format", trace_opts.format,
                    "din (Dinero IV, default), din-sized (din + access size) or bin")
      ->check(CLI::IsMember({"din", "din-sized", "bin"}));
  trace->add_option("--level", trace_opts.level,
                    "l1: the node-fetch stream (default); l2: the addresses of the requests the "
                    "shared L2 takes, in its order (din only; needs l2.enable)")
      ->check(CLI::IsMember({"l1", "l2"}));
  add_threads(trace);

  ReplayOptions replay_opts;
  auto* replay = app.add_subcommand("replay", "Replay a node trace through one cache (l1.*)");
  replay->add_option("trace", replay_opts.trace, "bin or din trace file")->required();
  add_set_option(replay, replay_opts.overrides,
                 "Cache parameter l1.size, l1.assoc, l1.line, l1.policy or l1.seed");

  RegressOptions regress_opts;
  auto* regress = app.add_subcommand("regress", "Rerun the reference cases; report every mismatch");
  regress->add_option("dir", regress_opts.dir, "Directory of cases (default: traces/ of the project)");
  regress->add_flag("--update", regress_opts.update,
                    "Rewrite every expected.json from this build (scripts/update_references.sh)");

  auto* sweep = add_sweep_subcommand(app);
  KeysOptions keys_opts;
  auto* keys =
      app.add_subcommand("keys", "List every config key (or, with --stats, every stats key)");
  keys->add_option("--format", keys_opts.format, "text (default), json, or markdown (README table)")
      ->check(CLI::IsMember({"text", "json", "markdown"}));
  keys->add_flag("--stats", keys_opts.stats,
                 "List the stats.json keys instead: kind, unit, description");

  // An unknown first word is named as such (CLI11 would only say a subcommand is required).
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
      known |= sub->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::cerr << "rtusim: unknown subcommand '" << argv[1] << "' (one of " << names
                << "; see rtusim --help)\n";
      return 2;
    }
  }
  install_output_cleanup();

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "rtusim: " << e.what() << " (see rtusim --help)\n";
    return 2;
  }

  std::optional<tbb::global_control> thread_limit;
  if (threads > 0)
    thread_limit.emplace(tbb::global_control::max_allowed_parallelism, size_t(threads));
  try {
    if (*run) return run_command(run_opts);
    if (*hits) return hits_command(hits_opts);
    if (*trace) return trace_command(trace_opts);
    if (*replay) return replay_command(replay_opts);
    if (*regress) return regress_command(regress_opts);
    if (*sweep) return sweep_command();
    if (*keys) return keys_command(keys_opts);
  } catch (const InputError& e) {
    std::cerr << "rtusim: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "rtusim: internal error: " << e.what() << "\n";
    return 1;
  }
  return 1;
}
