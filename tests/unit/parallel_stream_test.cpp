// --threads never changes a result, down to the fetch stream: what a backend receives (every
// fetch's stream, address and bytes, in order, and each ray's end with its pixel and kind) with
// 2 threads is what one thread sends it, ray by ray from plain traversal, in both ray orders.
// Totals, images and heatmaps can hide two fetches of one ray swapped; this cannot.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>
#include <unistd.h>

#include "app/pipeline.h"
#include "layout/layout_dispatch.h"
#include "scene/pinhole_camera.h"
#include "tracer/fetch_log.h"
#include "tracer/parallel_render.h"
#include "traversal/traversal.h"

namespace rtusim {
namespace {

// (stream, address, bytes) per fetch; a ray's end is (-1 - kind, pixel, 0).
using Event = std::tuple<int, uint64_t, uint32_t>;

// Records what it receives: from trace() (one thread: its own traversal of each ray) or from
// replay() (several threads: the logs the workers recorded).
class StreamBackend final : public TraceBackend {
 public:
  explicit StreamBackend(const MemoryImage& image) : image_(image) {}
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override {
    with_layout_decoder(image_, [&]<class Decoder>() {
      for (size_t i = 0; i < rays.size(); ++i) {
        hits[i] = traverse<Decoder>(image_, rays[i].ray, rays[i].any_hit(), *this);
        end_ray(rays[i].pixel, rays[i].kind, 0);
      }
    });
  }
  const MemoryImage* replay_image() const override { return &image_; }
  void replay(const FetchLog& log) override { log.replay(*this); }

  void fetch(Stream s, uint64_t addr, uint32_t bytes) {
    events.emplace_back(static_cast<int>(s), addr, bytes);
  }
  void end_ray(uint32_t pixel, RayKind kind, uint64_t /*direct_bytes*/) {
    events.emplace_back(-1 - static_cast<int>(kind), pixel, 0u);
  }
  std::vector<Event> events;

 private:
  const MemoryImage& image_;
};

TEST(ParallelStream, TwoThreadsSendTheOneThreadFetchStream) {
  constexpr int kW = 48, kH = 40;
  const std::filesystem::path cfg = std::filesystem::temp_directory_path() /
                                    ("rtusim_stream_" + std::to_string(::getpid()) + ".toml");
  std::ofstream(cfg) << "[scene]\npath = \"builtin:cornell\"\n[tracer]\nmax_depth = 4\n"
                        "[layout]\nkind = [\"dfl\", \"subtree\"]\n";
  const Prepared p = prepare_run(cfg.string(), {});
  std::filesystem::remove(cfg);
  const PinholeCamera camera(p.camera, kW, kH);
  for (const char* order : {"recursive", "wavefront"}) {
    TracerParams tracer = p.config.tracer;
    tracer.order = std::string(order) == "recursive" ? RayOrder::kRecursive : RayOrder::kWavefront;
    for (const MemoryImage& image : p.images) {
      SCOPED_TRACE(std::string(order) + " " + image.layout);
      std::vector<Event> stream[2];
      for (const int threads : {1, 2}) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        ASSERT_EQ(parallel_threads(), threads);
        StreamBackend backend(image);
        parallel_render(p.scene, tracer, backend, camera, kW, kH);
        stream[threads - 1] = std::move(backend.events);
      }
      ASSERT_GT(stream[0].size(), size_t(kW) * kH * 4);
      ASSERT_EQ(stream[0].size(), stream[1].size());
      size_t first = 0;
      while (first < stream[0].size() && stream[0][first] == stream[1][first]) ++first;
      EXPECT_EQ(first, stream[0].size()) << "the streams part at event " << first;
    }
  }
}

}  // namespace
}  // namespace rtusim
