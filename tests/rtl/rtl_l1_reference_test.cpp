// Lockstep equivalence on the reference cases (traces/*/config.toml, the `rtusim regress` set):
// each case's node stream is regenerated with the library (the Whitted frame in its ray order,
// every layout), expanded to line accesses as the functional tier counts them (a node that
// straddles two lines is two accesses), and replayed in blocking mode through the Verilated
// RTL build of the case's L1 and through SetAssocCache: every access has the same hit/miss
// outcome, and the RTL's totals equal the case's expected.json (l1.accesses, l1.misses per
// layout). Cases whose scene is missing ($RTUSIM_SCENES) or whose L1 is not built are skipped,
// and then so is the test (it does not pass on the built-in cases alone; in CI it fails).
#include <gtest/gtest.h>

#include "../skip_unless_ci.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/pipeline.h"
#include "cache/set_assoc_cache.h"
#include "layout/layout_dispatch.h"
#include "rtl/rtl_l1_registry.h"
#include "rtl_l1_harness.h"
#include "scene/pinhole_camera.h"
#include "tracer/whitted_tracer.h"
#include "traversal/traversal.h"
#include "util/error.h"

namespace rtusim::rtltest {
namespace {

// A TraceBackend that records the node stream as line addresses, in issue order.
class LineStreamBackend final : public TraceBackend {
 public:
  LineStreamBackend(const MemoryImage& image, uint32_t line_bytes, std::vector<uint64_t>& out)
      : image_(image), line_(line_bytes), out_(out) {}
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override {
    with_layout_decoder(image_, [&]<class Decoder>() {
      for (size_t i = 0; i < rays.size(); ++i)
        hits[i] = traverse<Decoder>(image_, rays[i].ray, rays[i].any_hit(), *this);
    });
  }
  void fetch(Stream s, uint64_t addr, uint32_t bytes) {
    if (s != Stream::kNode) return;
    for (uint64_t l = addr / line_; l <= (addr + bytes - 1) / line_; ++l) out_.push_back(l * line_);
  }

 private:
  const MemoryImage& image_;
  uint64_t line_;
  std::vector<uint64_t>& out_;
};

std::string source_dir() { return RTUSIM_SOURCE_DIR; }

TEST(RtlL1ReferenceCases, EveryAccessAgreesAndTotalsMatchExpected) {
  int cases = 0;
  std::vector<std::string> skipped;  // cases without their scene or their L1 build
  for (const auto& entry : std::filesystem::directory_iterator(source_dir() + "/traces")) {
    const std::filesystem::path config = entry.path() / "config.toml";
    if (!std::filesystem::exists(config)) continue;
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    Prepared p;
    try {
      p = prepare_run(config.string(), {});
    } catch (const InputError& e) {
      std::printf("%s: skipped (%s)\n", name.c_str(), e.what());
      skipped.push_back(name);
      continue;
    }
    // The blocking line stream is the functional tier's; timed tiers interleave rays.
    if (p.config.sim.tier != "functional") {
      std::printf("%s: skipped (sim.tier = %s: its totals are not the blocking stream's)\n",
                  name.c_str(), p.config.sim.tier.c_str());
      continue;
    }
    // A chip's l1.* are sums over its units' L1s, each with its own stream.
    if (!p.config.chip.single_unit()) {
      std::printf("%s: skipped (a chip: one L1 per unit)\n", name.c_str());
      continue;
    }
    const CacheParams& l1 = p.config.l1.params.cache;
    const RtlL1Build* build = find_rtl_l1_build(l1);
    if (!build) {
      std::printf("%s: skipped (L1 not built)\n", name.c_str());
      skipped.push_back(name);
      continue;
    }
    std::ifstream in(entry.path() / "expected.json");
    const nlohmann::json expected = nlohmann::json::parse(in);
    for (const MemoryImage& image : p.images) {
      SCOPED_TRACE(image.layout);
      std::vector<uint64_t> stream;
      LineStreamBackend backend(image, l1.line_bytes, stream);
      const int w = p.config.image.width, h = p.config.image.height;
      WhittedTracer(p.scene, p.config.tracer, backend).render(PinholeCamera(p.camera, w, h), w, h);

      auto rtl = make_cpp_model(std::string(build->model));
      ASSERT_TRUE(rtl);
      std::vector<Outcome> out;
      rtl->replay_blocking(stream, out);
      ASSERT_EQ(out.size(), stream.size());
      SetAssocCache ref(l1);
      uint64_t misses = 0;
      for (size_t i = 0; i < stream.size(); ++i) {
        const bool hit = ref.access(stream[i]);
        misses += hit ? 0 : 1;
        ASSERT_EQ(hit, out[i] == Outcome::kHit) << "access " << i;
      }
      const std::string prefix = p.images.size() > 1 ? "layout." + image.layout + "." : "";
      EXPECT_EQ(stream.size(), expected.at(prefix + "l1.accesses").get<uint64_t>());
      EXPECT_EQ(misses, expected.at(prefix + "l1.misses").get<uint64_t>());
      EXPECT_EQ(rtl->memory_requests(), misses);
      std::printf("%s %s %s: %zu accesses, %llu misses: identical, as expected.json\n",
                  name.c_str(), image.layout.c_str(), build->model.data(), stream.size(),
                  static_cast<unsigned long long>(misses));
    }
    ++cases;
  }
  EXPECT_GE(cases, 3);  // the built-in cases need no scene files
  if (!skipped.empty())
    RTUSIM_SKIP_UNLESS_CI(std::to_string(skipped.size()) + " cases skipped, " + skipped.front() +
                          " the first");
}

}  // namespace
}  // namespace rtusim::rtltest
