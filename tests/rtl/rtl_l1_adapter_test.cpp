// The RTL node L1 in the cycle tier (l1.model = rtl, rtl_model/rtl_l1_adapter.h), end to end
// through CycleBackend against the C++ L1Cache on the same rays: both implement the node L1
// timing spec v2, so with 1, 32 and 128 rays in flight, on every build (and with the data
// cache), every L1 counter, the node DRAM bytes and the cycle count are equal, and so is every
// node request's time, address and answer time (recorded between the unit and the L1). Plus
// the stopped clock, the config keys (unbuilt combinations) and the VCD (written only by a run
// that succeeds).
#include <gtest/gtest.h>

#include "../skip_unless_ci.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include <unistd.h>

#include "config/config_reader.h"
#include "mem/node_l1.h"
#include "model/cycle_backend.h"
#include "model/cycle_params.h"
#include "rtl/rtl_l1_registry.h"
#include "rtl_l1_adapter.h"
#include "sc_fixture.h"
#include "scene_fixture.h"
#include "tracer/host_backend.h"
#include "util/error.h"
#include "util/stats.h"

namespace rtusim {
namespace {

using testing::SceneFixture;

// One node request as the unit sees it: its time, its address, and when it was answered.
struct Access {
  uint64_t t_ps, addr, answer_ps;
  bool operator==(const Access&) const = default;
};

// A node L1 that records every request between the unit and a model (the C++ L1Cache or the
// RTL adapter) and forwards it unchanged; optionally throws at the n-th request (a failing run).
class RecordingL1 : public sc_core::sc_module, public NodeL1 {
 public:
  tlm_utils::simple_target_socket<RecordingL1> target_socket;
  tlm_utils::simple_initiator_socket<RecordingL1> initiator_socket;

  RecordingL1(const sc_core::sc_module_name& name, const std::string& model, const L1Params& p,
              const std::string& vcd_path, std::vector<Access>& log, uint64_t fail_at)
      : sc_module(name),
        target_socket("target_socket"),
        initiator_socket("initiator_socket"),
        inner_(model == "cpp" ? std::make_unique<L1Cache>("model", p)
                              : make_rtl_adapter("model", p, vcd_path)),
        log_(log),
        fail_at_(fail_at) {
    target_socket.register_nb_transport_fw(this, &RecordingL1::nb_transport_fw);
    initiator_socket.register_nb_transport_bw(this, &RecordingL1::nb_transport_bw);
    initiator_socket.bind(inner_->upstream());
  }

  tlm::tlm_target_socket<>& upstream() override { return target_socket; }
  tlm::tlm_initiator_socket<>& downstream() override { return inner_->downstream(); }
  uint64_t hits() const override { return inner_->hits(); }
  uint64_t primary_misses() const override { return inner_->primary_misses(); }
  uint64_t merged_misses() const override { return inner_->merged_misses(); }
  uint64_t mshr_stall_cycles() const override { return inner_->mshr_stall_cycles(); }
  double mean_miss_latency_cycles() const override { return inner_->mean_miss_latency_cycles(); }
  uint64_t bytes_from_dram() const override { return inner_->bytes_from_dram(); }
  const MemoryHorizon* horizon() const override { return inner_->horizon(); }
  void set_downstream_horizon(const MemoryHorizon* h) override {
    inner_->set_downstream_horizon(h);
  }

 private:
  tlm::tlm_sync_enum nb_transport_fw(tlm::tlm_generic_payload& trans, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay) {
    if (phase == tlm::BEGIN_REQ) {
      if (fail_at_ && log_.size() + 1 == fail_at_)
        throw std::runtime_error("recording l1: failing on purpose");
      open_[&trans] = log_.size();
      log_.push_back({now_ps() + delay.value(), trans.get_address(), 0});
    }
    const tlm::tlm_sync_enum s = initiator_socket->nb_transport_fw(trans, phase, delay);
    if (s == tlm::TLM_COMPLETED && open_.count(&trans)) answered(trans, now_ps() + delay.value());
    return s;
  }
  tlm::tlm_sync_enum nb_transport_bw(tlm::tlm_generic_payload& trans, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay) {
    if (phase == tlm::BEGIN_RESP) answered(trans, now_ps() + delay.value());
    return target_socket->nb_transport_bw(trans, phase, delay);
  }
  void answered(tlm::tlm_generic_payload& trans, uint64_t at_ps) {
    log_.at(open_.at(&trans)).answer_ps = at_ps;
    open_.erase(&trans);
  }

  std::unique_ptr<NodeL1> inner_;
  std::vector<Access>& log_;
  uint64_t fail_at_;
  std::unordered_map<const tlm::tlm_generic_payload*, size_t> open_;  // -> log index
};

// The recorder sits in the node L1 seam's rtl slot (the only one a test can fill), wrapping
// whichever model the next run names.
struct RecordingSetup {
  std::string model;
  std::vector<Access>* log = nullptr;
  uint64_t fail_at = 0;
};
RecordingSetup g_recording;

std::unique_ptr<NodeL1> make_recording(const char* name, const L1Params& p,
                                       const std::string& vcd_path) {
  return std::make_unique<RecordingL1>(name, g_recording.model, p, vcd_path, *g_recording.log,
                                       g_recording.fail_at);
}

struct RunResult {
  Stats stats;
  std::vector<Hit> hits;
  std::vector<Access> accesses;
  uint64_t cycles = 0;
  double seconds = 0;
};

// Runs the fixture's rays in two batches (the RTL's clock stops in between and time
// accumulates). `record`: through RecordingL1 around `model`.
RunResult run(const SceneFixture& f, CycleParams p, const std::string& model, bool record,
              const std::string& vcd = "") {
  RunResult r;
  p.node_l1_model = record ? "rtl" : model;
  p.vcd_path = vcd;
  p.finish();
  if (record) {
    g_recording = {model, &r.accesses, 0};
    register_rtl_node_l1(&make_recording);
  }
  r.hits.resize(f.rays.size());
  const auto t0 = std::chrono::steady_clock::now();
  {
    CycleBackend backend(f.image, p);  // elaborates in a context of its own
    const std::span<const RayRecord> all(f.rays);
    const size_t half = all.size() / 2;
    backend.trace(all.first(half), std::span<Hit>(r.hits).first(half));
    backend.trace(all.subspan(half), std::span<Hit>(r.hits).subspan(half));
    backend.write_stats(r.stats);
    r.cycles = backend.cycles();
    backend.finish();  // the run succeeded: its files go into place
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  register_rtl_node_l1(&make_rtl_adapter);
  return r;
}

uint64_t u(const RunResult& r, const char* key) { return r.stats.at(key).get<uint64_t>(); }
double d(const RunResult& r, const char* key) { return r.stats.at(key).get<double>(); }

void expect_same_hits(const RunResult& a, const RunResult& b) {
  ASSERT_EQ(a.hits.size(), b.hits.size());
  for (size_t i = 0; i < a.hits.size(); ++i) {
    ASSERT_EQ(a.hits[i].triangle, b.hits[i].triangle) << "ray " << i;
    ASSERT_EQ(a.hits[i].t, b.hits[i].t) << "ray " << i;
  }
}

// Every node request: the same time, address and answer time, in the same order.
void expect_same_accesses(const RunResult& cpp, const RunResult& rtl) {
  EXPECT_EQ(cpp.accesses.size(), rtl.accesses.size());
  const size_t n = std::min(cpp.accesses.size(), rtl.accesses.size());
  for (size_t i = 0; i < n; ++i) {
    const Access& a = cpp.accesses[i];
    const Access& b = rtl.accesses[i];
    if (a == b) continue;
    ADD_FAILURE() << "node request " << i << " of " << n << ": cpp (t " << a.t_ps << " ps, addr 0x"
                  << std::hex << a.addr << std::dec << ", answered " << a.answer_ps
                  << " ps), rtl (t " << b.t_ps << " ps, addr 0x" << std::hex << b.addr
                  << std::dec << ", answered " << b.answer_ps << " ps)";
    return;
  }
}

void report(const std::string& what, const RunResult& cpp, const RunResult& rtl) {
  std::printf("%s: cpp %llu cycles, %llu hits, %llu primary, %llu merged, %llu stall cycles, "
              "%.3f mean miss latency; rtl %+lld cycles; %zu node requests, %.2f s cpp, %.2f s "
              "rtl\n",
              what.c_str(), (unsigned long long)cpp.cycles, (unsigned long long)u(cpp, "l1.hits"),
              (unsigned long long)u(cpp, "l1.primary_misses"),
              (unsigned long long)u(cpp, "l1.merged_misses"),
              (unsigned long long)u(cpp, "l1.mshr_stall_cycles"),
              d(cpp, "l1.mean_miss_latency_cycles"),
              (long long)rtl.cycles - (long long)cpp.cycles, cpp.accesses.size(), cpp.seconds,
              rtl.seconds);
}

CycleParams params_for(const RtlL1Build& b, uint32_t rays_in_flight) {
  CycleParams p;
  p.node_l1.cache.size_bytes = b.size_bytes;
  p.node_l1.cache.assoc = b.assoc;
  p.node_l1.cache.line_bytes = b.line_bytes;
  p.node_l1.cache.policy = std::string(b.policy);
  p.unit.rays_in_flight = rays_in_flight;
  return p;
}

class RtlAdapterTest : public testing::SystemCTest {
 protected:
  void SetUp() override {
    testing::SystemCTest::SetUp();
    if (!rtl_node_l1_linked()) RTUSIM_SKIP_UNLESS_CI("no RTL L1 linked");
  }
};

// Everything the comparison covers: hits, counters, node DRAM bytes, cycles, node requests.
void expect_equal(const RunResult& cpp, const RunResult& rtl) {
  expect_same_hits(cpp, rtl);
  for (const char* key : {"l1.accesses", "l1.hits", "l1.misses", "l1.primary_misses",
                          "l1.merged_misses", "l1.mshr_stall_cycles", "dram.bytes.nodes",
                          "dram.bytes.total", "traversal.node_fetches"})
    EXPECT_EQ(u(cpp, key), u(rtl, key)) << key;
  EXPECT_EQ(d(cpp, "l1.mean_miss_latency_cycles"), d(rtl, "l1.mean_miss_latency_cycles"));
  EXPECT_EQ(cpp.cycles, rtl.cycles);
  expect_same_accesses(cpp, rtl);
}

// The spec's promise: l1.model cpp and rtl are the same cycle-level machine, at any load.
class RtlAdapterEquality : public RtlAdapterTest, public ::testing::WithParamInterface<uint32_t> {};

TEST_P(RtlAdapterEquality, EqualsCppL1ExactlyOnEveryBuild) {
  const uint32_t rays_in_flight = GetParam();
  SceneFixture f("dfl");
  for (const RtlL1Build& b : rtl_l1_builds()) {
    const std::string what = std::string(b.model) + ", " + std::to_string(rays_in_flight) +
                             " in flight";
    SCOPED_TRACE(what);
    const CycleParams p = params_for(b, rays_in_flight);
    const RunResult cpp = run(f, p, "cpp", true);
    const RunResult rtl = run(f, p, "rtl", true);
    report(what, cpp, rtl);
    expect_equal(cpp, rtl);
    EXPECT_GT(u(rtl, "l1.primary_misses"), 100u);
    if (rays_in_flight == 1) {
      EXPECT_EQ(u(rtl, "l1.merged_misses"), 0u);
    } else {
      EXPECT_GT(u(rtl, "l1.merged_misses"), 0u);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(RaysInFlight, RtlAdapterEquality, ::testing::Values(1u, 32u, 128u),
                         [](const ::testing::TestParamInfo<uint32_t>& i) {
                           return std::to_string(i.param);
                         });

// With the data cache (a C++ L1Cache) between the unit and DRAM for lists and triangles.
TEST_F(RtlAdapterTest, EqualsCppL1ExactlyWithTheDataCache) {
  SceneFixture f("dfl");
  CycleParams p;
  p.unit.rays_in_flight = 32;
  p.data_cache = L1Params{};
  const RunResult cpp = run(f, p, "cpp", true);
  const RunResult rtl = run(f, p, "rtl", true);
  report("8192/4/64 lru with the data cache, 32 in flight", cpp, rtl);
  expect_equal(cpp, rtl);
  EXPECT_EQ(u(cpp, "dcache.misses"), u(rtl, "dcache.misses"));
}

// The recorder is transparent: a recorded run gives the counters and cycles of a direct one.
TEST_F(RtlAdapterTest, RecordingChangesNothing) {
  SceneFixture f("odfl");
  CycleParams p;
  p.unit.rays_in_flight = 32;
  for (const char* model : {"cpp", "rtl"}) {
    SCOPED_TRACE(model);
    const RunResult direct = run(f, p, model, false);
    const RunResult recorded = run(f, p, model, true);
    EXPECT_EQ(direct.cycles, recorded.cycles);
    for (const char* key : {"l1.hits", "l1.primary_misses", "l1.merged_misses",
                            "l1.mshr_stall_cycles", "dram.bytes.nodes"})
      EXPECT_EQ(u(direct, key), u(recorded, key)) << key;
    EXPECT_EQ(recorded.accesses.size(), u(direct, "l1.accesses"));
  }
}

// Stopping the clock while only fills are awaited (or a refused request waits for one) is
// invisible: the same run with a clock that runs until every request is answered gives the same
// cycles and counters.
std::unique_ptr<NodeL1> make_always_clocked(const char* name, const L1Params& p,
                                            const std::string& vcd_path) {
  return std::make_unique<RtlL1Adapter>(name, p, vcd_path, false);
}

TEST_F(RtlAdapterTest, StoppingTheClockWhileFillsAreAwaitedChangesNothing) {
  SceneFixture f("odfl");
  for (uint32_t rays_in_flight : {1u, 32u, 128u}) {
    SCOPED_TRACE(rays_in_flight);
    CycleParams p;
    p.unit.rays_in_flight = rays_in_flight;
    const RunResult gated = run(f, p, "rtl", false);
    register_rtl_node_l1(&make_always_clocked);
    const RunResult clocked = run(f, p, "rtl", false);  // restores make_rtl_adapter
    std::printf("%u in flight: %.3f s with the clock stopped while fills are awaited, %.3f s "
                "without\n", rays_in_flight, gated.seconds, clocked.seconds);
    EXPECT_EQ(gated.cycles, clocked.cycles);
    for (const char* key : {"l1.hits", "l1.primary_misses", "l1.merged_misses",
                            "l1.mshr_stall_cycles", "dram.bytes.nodes", "dram.row_hits"})
      EXPECT_EQ(u(gated, key), u(clocked, key)) << key;
    EXPECT_EQ(d(gated, "l1.mean_miss_latency_cycles"), d(clocked, "l1.mean_miss_latency_cycles"));
    if (rays_in_flight == 128) {
      EXPECT_GT(u(gated, "l1.mshr_stall_cycles"), 0u);
    }
  }
}

ConfigReader config(const std::string& text) { return ConfigReader::from_string(text, "test"); }

TEST(RtlAdapterConfig, ModelKeyDefaultsToCpp) {
  ConfigReader r = config("");
  EXPECT_EQ(read_cycle_params(r).node_l1_model, "cpp");
  ConfigReader r2 = config("[l1]\nmodel = \"rtl\"\n");
  EXPECT_EQ(read_cycle_params(r2).node_l1_model, "rtl");
  ConfigReader r3 = config("[l1]\nmodel = \"verilog\"\n");
  EXPECT_THROW(read_cycle_params(r3), InputError);
}

TEST(RtlAdapterConfig, UnbuiltCombinationNamesItAndListsTheBuilt) {
  ConfigReader r = config("[l1]\nmodel = \"rtl\"\nsize = 2048\n");
  try {
    read_cycle_params(r);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("l1.size=2048"), std::string::npos) << m;
    EXPECT_NE(m.find("built: " + rtl_l1_builds_text()), std::string::npos) << m;
  }
  ConfigReader mshrs = config("[l1]\nmodel = \"rtl\"\nmshrs = 4\n");
  try {
    read_cycle_params(mshrs);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("l1.mshrs=4"), std::string::npos) << e.what();
  }
  ConfigReader cpp = config("[l1]\nsize = 2048\n");  // the C++ L1 takes any geometry
  EXPECT_NO_THROW(read_cycle_params(cpp));
  // With the C++ L1, sim.vcd dumps the unit's state (tests/cli/tier_consistency.sh).
  ConfigReader vcd = config("[sim]\nvcd = \"x.vcd\"\n");
  EXPECT_EQ(read_cycle_params(vcd).vcd_path, "x.vcd");
}

std::filesystem::path vcd_dir() {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("rtusim_rtl_vcd_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

TEST_F(RtlAdapterTest, VcdOfTheRtlSignalsAppearsWhenTheRunSucceeds) {
  SceneFixture f("dfl");
  f.rays.resize(40);
  const auto dir = vcd_dir();
  const std::string path = (dir / "l1.vcd").string();
  ConfigReader r = config("[sim]\nvcd = \"" + path + "\"\n[l1]\nmodel = \"rtl\"\n");
  const CycleParams p = read_cycle_params(r);
  const RunResult traced = run(f, p, "rtl", false, p.vcd_path);
  const RunResult plain = run(f, p, "rtl", false);  // the clock's shape is not observable
  EXPECT_EQ(traced.cycles, plain.cycles);
  EXPECT_EQ(u(traced, "l1.misses"), u(plain, "l1.misses"));
  EXPECT_GT(u(traced, "l1.accesses"), 0u);
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  std::stringstream text;
  text << in.rdbuf();
  for (const char* signal : {"clk", "i_req_valid", "o_req_ready", "o_req_hit", "o_req_mshr",
                             "o_resp_id", "o_mem_req_addr", "i_mem_resp_valid", "o_fill_mshr",
                             "o_mshrs_busy"})
    EXPECT_NE(text.str().find(signal), std::string::npos) << signal;
  EXPECT_NE(text.str().find("#"), std::string::npos);  // value changes over time
  // Nothing else is left in the directory (no temporary file).
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()), 1);
  std::filesystem::remove_all(dir);
}

TEST_F(RtlAdapterTest, VcdOfAFailingRunIsNotWritten) {
  SceneFixture f("dfl");
  f.rays.resize(40);
  const auto dir = vcd_dir();
  CycleParams p;
  p.node_l1_model = "rtl";
  p.vcd_path = (dir / "l1.vcd").string();
  p.finish();
  std::vector<Access> log;
  g_recording = {"rtl", &log, 50};  // throws at the 50th node request
  register_rtl_node_l1(&make_recording);
  std::vector<Hit> hits(f.rays.size());
  EXPECT_ANY_THROW({
    CycleBackend backend(f.image, p);
    backend.trace(f.rays, hits);
  });
  register_rtl_node_l1(&make_rtl_adapter);
  EXPECT_EQ(log.size(), 49u);
  EXPECT_TRUE(std::filesystem::is_empty(dir)) << "a VCD or a temporary file was left";
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rtusim
