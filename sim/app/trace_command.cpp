// `rtusim trace`: the node-fetch address stream of one layout (or, with --level l2, the shared
// L2's input), as a din or bin trace file.
#include <cstdio>
#include <sstream>

#include "app/commands.h"
#include "app/pipeline.h"
#include "app/node_stream.h"
#include "trace/trace_format.h"
#include "util/error.h"
#include "util/output_files.h"

namespace rtusim {

int trace_command(const TraceOptions& opts) {
  const TraceFormat format = opts.format == "bin"         ? TraceFormat::kBin
                             : opts.format == "din-sized" ? TraceFormat::kDinSized
                                                          : TraceFormat::kDin;
  const bool l2_level = opts.level == "l2";
  if (l2_level && format != TraceFormat::kDin)
    throw InputError("--format " + opts.format +
                     ": --level l2 writes din only (the L2 takes lines and bursts of several "
                     "sizes)");
  OutputFile file(opts.out);  // checks the directory before any work
  {
    // The layout check before the scene is loaded and the tree built.
    const RunConfig c = load_run_config(opts.config, opts.overrides);
    if (c.layout.kinds.size() != 1) {
      std::string kinds;
      for (const auto& k : c.layout.kinds) kinds += (kinds.empty() ? "" : ", ") + k;
      throw InputError(c.origins.at("layout.kind") + ": layout.kind: trace takes one layout, got " +
                       std::to_string(c.layout.kinds.size()) + " (" + kinds +
                       "); pick one with --set layout.kind=NAME");
    }
    // The stream is the plain functional tier's, one ray at a time over the whole frame: a
    // config that asks for another order or part of the frame would get a trace that is not
    // its run's.
    const auto refuse = [&](const char* key, const std::string& what) {
      throw InputError(c.origins.at(key) + ": " + key + ": " + what +
                       ": trace records the whole frame's node stream one ray at a time (the "
                       "plain functional tier's); set it back to its default");
    };
    if (c.functional.rays_in_flight > 1)
      refuse("functional.rays_in_flight", std::to_string(c.functional.rays_in_flight));
    if (c.functional.timed) refuse("functional.timed", "true");
    if (c.chip.units > 1 && !l2_level) refuse("chip.units", std::to_string(c.chip.units));
    if (l2_level && !c.chip.l2)
      throw InputError(c.origins.at("l2.enable") +
                       ": l2.enable: false: --level l2 records the shared L2's input; set "
                       "l2.enable = true");
    const auto text = [](double v) {
      std::ostringstream os;
      os << v;
      return os.str();
    };
    if (c.sample.rate < 1.0) refuse("sample.rate", text(c.sample.rate));
    if (c.sample.target_ci > 0.0) refuse("sample.target_ci", text(c.sample.target_ci));
  }
  const Prepared p = prepare_run(opts.config, opts.overrides);
  const MemoryImage& image = p.images.front();
  TraceWriter writer(file.temp_path(), format, image.layout, image.node_bytes, image_hash(image),
                     file.name());
  if (l2_level)
    write_l2_stream(p, image, writer);
  else
    write_node_stream(p, image, writer);
  writer.finish();
  file.commit();
  std::printf("trace: %llu %s, layout %s, %dx%d, %s, checksum %s -> %s\n",
              static_cast<unsigned long long>(writer.digest().count),
              l2_level ? "L2 requests" : "node fetches", image.layout.c_str(),
              p.config.image.width, p.config.image.height, opts.format.c_str(),
              hex64(writer.digest().checksum).c_str(), opts.out.c_str());
  return 0;
}

}  // namespace rtusim
