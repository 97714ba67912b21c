// `rtusim trace`: the node-fetch address stream of one layout, as a din or bin trace file.
#include <cstdio>

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
  }
  const Prepared p = prepare_run(opts.config, opts.overrides);
  const MemoryImage& image = p.images.front();
  TraceWriter writer(file.temp_path(), format, image.layout, image.node_bytes, image_hash(image));
  write_node_stream(p, image, writer);
  writer.finish();
  file.commit();
  std::printf("trace: %llu node fetches, layout %s, %dx%d, %s, checksum %s -> %s\n",
              static_cast<unsigned long long>(writer.digest().count), image.layout.c_str(),
              p.config.image.width, p.config.image.height, opts.format.c_str(),
              hex64(writer.digest().checksum).c_str(), opts.out.c_str());
  return 0;
}

}  // namespace rtusim
