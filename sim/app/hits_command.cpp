// `rtusim hits`: primary-ray hits in the contract's RTH1 file format.
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>

#include "app/commands.h"
#include "app/pipeline.h"
#include "scene/pinhole_camera.h"
#include "tracer/host_backend.h"
#include "tracer/parallel_render.h"
#include "util/error.h"
#include "util/output_files.h"

namespace rtusim {

int hits_command(const RunOptions& opts) {
  OutputFile file(opts.out);  // checks the directory before any work
  const Prepared p = prepare_run(opts.config, opts.overrides);
  const int w = p.config.image.width, h = p.config.image.height;
  const PinholeCamera camera(p.camera, w, h);

  std::vector<RayRecord> rays(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      RayRecord& r = rays[size_t(y) * w + x];
      r.ray = camera.generate(x, y);
      r.pixel = static_cast<uint32_t>(y * w + x);
    }
  std::vector<Hit> hits(rays.size());
  HostBackend backend(p.images.front());
  if (parallel_threads() > 1) ParallelBackend(backend).trace(rays, hits);
  else backend.trace(rays, hits);

  // RTH1, u32 W, u32 H, u32 0, f32 t per pixel (+inf = miss), i32 triangle id (-1 = miss).
  std::ofstream out(file.temp_path(), std::ios::binary);
  auto put_u32 = [&](uint32_t v) {
    unsigned char b[4] = {uint8_t(v), uint8_t(v >> 8), uint8_t(v >> 16), uint8_t(v >> 24)};
    out.write(reinterpret_cast<const char*>(b), 4);
  };
  out.write("RTH1", 4);
  put_u32(static_cast<uint32_t>(w));
  put_u32(static_cast<uint32_t>(h));
  put_u32(0);
  for (const Hit& hit : hits) {
    uint32_t bits;
    std::memcpy(&bits, &hit.t, 4);
    put_u32(bits);
  }
  for (const Hit& hit : hits) put_u32(hit.valid() ? hit.triangle : 0xffffffffu);
  out.close();
  if (!out) throw InputError(opts.out + ": cannot write (" + std::strerror(errno) + ")");
  file.commit();
  uint64_t hit_count = 0;
  for (const Hit& hit : hits) hit_count += hit.valid();
  std::cout << "hits: " << w << "x" << h << ", " << hit_count << " of " << hits.size()
            << " primary rays hit -> " << opts.out << "\n";
  return 0;
}

}  // namespace rtusim
