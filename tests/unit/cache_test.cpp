// Cache model: hand-computed sequences per policy, validation, the stream fetch sink, and an
// exact comparison of miss counts with the independent Python model tests/cache_ref.py.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../skip_unless_ci.h"
#include <unistd.h>

#include "cache/cache_params.h"
#include "cache/policy/random_policy.h"
#include "cache/replacement_policy.h"
#include "cache/set_assoc_cache.h"
#include "cache/fetch_cache.h"
#include "util/error.h"
#include "util/stats.h"

namespace rtusim {
namespace {

CacheParams geometry(uint64_t size, uint32_t assoc, uint32_t line, const std::string& policy,
                     uint64_t seed = 1) {
  CacheParams p;
  p.size_bytes = size;
  p.assoc = assoc;
  p.line_bytes = line;
  p.policy = policy;
  p.seed = seed;
  return p;
}

// Per-access hit (1) / miss (0) string of a sequence.
std::string hit_pattern(SetAssocCache& c, const std::vector<uint64_t>& addrs) {
  std::string s;
  for (uint64_t a : addrs) s += c.access(a) ? '1' : '0';
  return s;
}

// A trace with locality: sequential runs, a hot region, and random jumps, unaligned addresses.
std::vector<uint64_t> clustered_trace(size_t n, uint64_t seed) {
  SplitMix64 rng(seed);
  std::vector<uint64_t> t;
  t.reserve(n);
  uint64_t a = 0;
  for (size_t i = 0; i < n; ++i) {
    const uint32_t r = rng.below(100);
    if (r < 55) a += 4 + rng.below(16);                         // walk on
    else if (r < 80) a = rng.below(6 * 1024);                   // hot region
    else if (r < 95) a = 0x10000 + rng.below(48 * 1024);        // warm region
    else a = rng.below(1u << 22);                               // anywhere in 4 MB
    t.push_back(a);
  }
  return t;
}

TEST(CacheTest, DirectMappedConflicts) {
  SetAssocCache c(geometry(256, 1, 64, "lru"));  // 4 sets of one way
  // 0x000, 0x100, 0x200 all map to set 0; 0x040 to set 1; 0x004 shares 0x000's line.
  EXPECT_EQ(hit_pattern(c, {0x000, 0x100, 0x000, 0x040, 0x040, 0x004, 0x200, 0x03f, 0x104}),
            "000011000");
  EXPECT_EQ(c.accesses(), 9u);
  EXPECT_EQ(c.hits(), 2u);
  EXPECT_EQ(c.misses(), 7u);
  EXPECT_EQ(c.bytes_from_dram(), 7u * 64);
}

TEST(CacheTest, TwoWayLruAndFifoDiffer) {
  // One set of two ways; lines A, B, C.
  const uint64_t A = 0, B = 64, C = 128;
  SetAssocCache lru(geometry(128, 2, 64, "lru"));
  SetAssocCache fifo(geometry(128, 2, 64, "fifo"));
  // The hit on A makes B least recent (LRU evicts B for C) but not first in (FIFO evicts A).
  EXPECT_EQ(hit_pattern(lru, {A, B, A, C, A, B}), "001010");
  EXPECT_EQ(hit_pattern(fifo, {A, B, A, C, A, B}), "001000");
  EXPECT_EQ(lru.misses(), 4u);
  EXPECT_EQ(fifo.misses(), 5u);
}

TEST(CacheTest, TreePlruVictimOrderFourWays) {
  TreePlruPolicy p(1, 4, 0);
  for (uint32_t w = 0; w < 4; ++w) p.fill(0, w);
  // Touching each victim in turn visits the ways in the classic order 0, 2, 1, 3, 0.
  std::vector<uint32_t> victims;
  for (int i = 0; i < 5; ++i) {
    victims.push_back(p.victim(0));
    p.fill(0, victims.back());
  }
  EXPECT_EQ(victims, (std::vector<uint32_t>{0, 2, 1, 3, 0}));

  // A hit moves the victim away from the touched half.
  TreePlruPolicy q(1, 4, 0);
  for (uint32_t w = 0; w < 4; ++w) q.fill(0, w);
  q.touch(0, 0);  // b1 = 1 (right older), b2 = 1
  EXPECT_EQ(q.victim(0), 2u);
  q.touch(0, 3);  // b1 = 0, b3 = 0
  EXPECT_EQ(q.victim(0), 1u);
}

TEST(CacheTest, TreePlruVictimEightWays) {
  TreePlruPolicy p(1, 8, 0);
  for (uint32_t w = 0; w < 8; ++w) p.fill(0, w);
  std::vector<uint32_t> victims;
  for (int i = 0; i < 8; ++i) {
    victims.push_back(p.victim(0));
    p.fill(0, victims.back());
  }
  EXPECT_EQ(victims, (std::vector<uint32_t>{0, 4, 2, 6, 1, 5, 3, 7}));
}

TEST(CacheTest, TreePlruDiffersFromLruInCache) {
  // One set of 4 ways: A B C D fill ways 0..3, E evicts A in both; then F evicts C under
  // tree-PLRU (the root bit points right after E refilled way 0) but B under LRU.
  const uint64_t A = 0, B = 64, C = 128, D = 192, E = 256, F = 320;
  SetAssocCache plru(geometry(256, 4, 64, "tree-plru"));
  SetAssocCache lru(geometry(256, 4, 64, "lru"));
  for (SetAssocCache* c : {&plru, &lru})
    for (uint64_t a : {A, B, C, D, E, F}) c->access(a);
  EXPECT_FALSE(plru.contains(A));
  EXPECT_TRUE(plru.contains(B));
  EXPECT_FALSE(plru.contains(C));
  EXPECT_TRUE(plru.contains(D) && plru.contains(E) && plru.contains(F));
  EXPECT_FALSE(lru.contains(A));
  EXPECT_FALSE(lru.contains(B));
  EXPECT_TRUE(lru.contains(C) && lru.contains(D) && lru.contains(E) && lru.contains(F));
  EXPECT_TRUE(plru.access(B));
  EXPECT_FALSE(lru.access(B));
}

TEST(CacheTest, RandomPolicyIsDeterministic) {
  const auto trace = clustered_trace(20000, 7);
  auto run = [&](uint64_t seed) {
    SetAssocCache c(geometry(1024, 4, 64, "random", seed));
    std::string pattern;
    for (uint64_t a : trace) pattern += c.access(a) ? '1' : '0';
    return pattern;
  };
  const std::string a1 = run(1), a2 = run(1), b = run(2), c = run(12345);
  EXPECT_EQ(a1, a2);
  EXPECT_NE(a1, b);
  EXPECT_NE(a1, c);
  EXPECT_NE(b, c);
}

TEST(CacheTest, RangeAccessCrossingLines) {
  SetAssocCache c(geometry(8192, 4, 64, "lru"));
  EXPECT_EQ(c.access_range(60, 8), 2u);   // bytes 60..67: lines 0 and 1, both miss
  EXPECT_EQ(c.accesses(), 2u);
  EXPECT_EQ(c.access_range(64, 36), 0u);  // line 1 only: hit
  EXPECT_EQ(c.access_range(100, 36), 1u); // 100..135: line 1 hits, line 2 misses
  EXPECT_EQ(c.access_range(127, 1), 0u);  // last byte of line 1
  EXPECT_EQ(c.access_range(500, 0), 0u);  // nothing touched
  EXPECT_EQ(c.accesses(), 6u);
  EXPECT_EQ(c.hits(), 3u);
  EXPECT_EQ(c.misses(), 3u);
  EXPECT_EQ(c.bytes_from_dram(), 3u * 64);
  EXPECT_EQ(c.access_range(0, 256), 1u);  // lines 0..3: 0, 1, 2 present, 3 new
}

TEST(CacheTest, RuntimePolicyMatchesConcreteAndVirtual) {
  const auto trace = clustered_trace(50000, 3);
  for (const std::string& policy : known_replacement_policies()) {
    const CacheParams p = geometry(4096, 4, 32, policy, 9);
    SetAssocCache runtime(p);
    SetAssocCache through_virtual = SetAssocCache::through_virtual_policy(p);
    EXPECT_STREQ(runtime.policy_name(), policy.c_str());
    EXPECT_STREQ(through_virtual.policy_name(), policy.c_str());
    uint64_t concrete_misses = 0;
    if (policy == "lru") concrete_misses = BasicSetAssocCache<LruPolicy>(p).replay(trace);
    if (policy == "tree-plru") concrete_misses = BasicSetAssocCache<TreePlruPolicy>(p).replay(trace);
    if (policy == "fifo") concrete_misses = BasicSetAssocCache<FifoPolicy>(p).replay(trace);
    if (policy == "random") concrete_misses = BasicSetAssocCache<RandomPolicy>(p).replay(trace);
    uint64_t runtime_misses = 0;
    for (uint64_t a : trace) runtime_misses += runtime.access(a) ? 0 : 1;
    EXPECT_EQ(runtime_misses, concrete_misses) << policy;
    EXPECT_EQ(through_virtual.replay(trace), concrete_misses) << policy;
    EXPECT_EQ(runtime.misses(), concrete_misses) << policy;
  }
}

std::string validation_error(const CacheParams& p) {
  try {
    validate(p, "l1");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CacheTest, ValidationNamesTheKey) {
  EXPECT_EQ(validation_error(geometry(8000, 4, 64, "lru")),
            "l1.size: 8000 is not a multiple of l1.line x l1.assoc (256)");
  EXPECT_EQ(validation_error(geometry(8192, 4, 48, "lru")), "l1.line: 48 must be a power of two >= 4");
  EXPECT_EQ(validation_error(geometry(8192, 4, 2, "lru")), "l1.line: 2 must be a power of two >= 4");
  EXPECT_EQ(validation_error(geometry(8192, 0, 64, "lru")), "l1.assoc: 0 must be at least 1");
  EXPECT_EQ(validation_error(geometry(128, 4, 64, "lru")),
            "l1.size: 128 is smaller than l1.line x l1.assoc (256)");
  EXPECT_EQ(validation_error(geometry(96 * 256, 4, 64, "lru")).rfind("l1.size: 24576 gives 96 sets", 0), 0u);
  EXPECT_EQ(validation_error(geometry(8192, 4, 64, "mru")),
            "l1.policy: unknown policy \"mru\" (known: lru, tree-plru, fifo, random)");
  EXPECT_EQ(validation_error(geometry(768, 3, 64, "tree-plru")),
            "l1.assoc: 3 must be a power of two for l1.policy = \"tree-plru\"");
  EXPECT_EQ(validation_error(geometry(768, 3, 64, "lru")), "");   // 4 sets of 3 ways
  EXPECT_EQ(validation_error(geometry(512, 8, 64, "tree-plru")), "");  // fully associative
  EXPECT_EQ(validation_error(geometry(8192, 4, 64, "lru")), "");
  EXPECT_THROW(SetAssocCache(geometry(8000, 4, 64, "lru")), InputError);
}

TEST(CacheTest, FactoryChoosesByName) {
  for (const std::string& name : known_replacement_policies())
    EXPECT_STREQ(make_replacement_policy(name, 4, 4, 1)->name(), name.c_str());
  try {
    make_replacement_policy("mru", 4, 4, 1);
    FAIL() << "no error for an unknown policy";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lru, tree-plru, fifo, random"), std::string::npos);
  }
}

TEST(CacheTest, FullyAssociativeLru) {
  SetAssocCache c(geometry(512, 8, 64, "lru"));  // one set of 8 ways
  std::vector<uint64_t> lines;
  for (uint64_t i = 0; i < 8; ++i) lines.push_back(i * 4096);  // would all conflict if set-indexed
  for (uint64_t a : lines) EXPECT_FALSE(c.access(a));
  for (uint64_t a : lines) EXPECT_TRUE(c.access(a));
  EXPECT_FALSE(c.access(9 * 4096));  // evicts line 0, the least recent
  EXPECT_FALSE(c.contains(0));
  EXPECT_TRUE(c.contains(4096));
}

// --- Against the independent Python model -----------------------------------------------------

std::filesystem::path tests_dir() {
  if (const char* env = std::getenv("RTUSIM_TEST_DATA")) return std::filesystem::path(env).parent_path();
#ifdef RTUSIM_TEST_DATA
  return std::filesystem::path(RTUSIM_TEST_DATA).parent_path();
#else
  return {};
#endif
}

std::string run_capture(const std::string& command) {
  std::string out;
  FILE* f = popen(command.c_str(), "r");
  if (!f) return out;
  char buf[256];
  while (fgets(buf, sizeof buf, f)) out += buf;
  pclose(f);
  return out;
}

TEST(CacheTest, MatchesPythonReferenceModel) {
  if (std::system("python3 -c pass > /dev/null 2>&1") != 0) RTUSIM_SKIP_UNLESS_CI("python3 not found");
  const std::filesystem::path script = tests_dir() / "cache_ref.py";
  ASSERT_TRUE(std::filesystem::exists(script)) << script;

  const auto trace = clustered_trace(40000, 2024);
  const std::filesystem::path trace_path =
      std::filesystem::temp_directory_path() /
      ("rtusim_cache_test_" + std::to_string(::getpid()) + ".din");
  {
    std::ofstream out(trace_path);
    char line[32];
    for (uint64_t a : trace) {
      std::snprintf(line, sizeof line, "0 %llx\n", static_cast<unsigned long long>(a));
      out << line;
    }
  }
  struct Geometry {
    uint64_t size;
    uint32_t assoc, line;
  };
  const std::vector<std::string> policies = {"lru", "fifo", "tree-plru", "random"};
  for (const Geometry g : {Geometry{8192, 4, 64}, Geometry{4096, 2, 32}, Geometry{16384, 8, 64},
                           Geometry{1024, 1, 64}, Geometry{512, 8, 64}}) {
    const std::string command = "python3 '" + script.string() + "' '" + trace_path.string() +
                                "' " + std::to_string(g.size) + " " + std::to_string(g.assoc) +
                                " " + std::to_string(g.line) + " lru,fifo,tree-plru,random";
    std::map<std::string, uint64_t> expected;
    std::istringstream lines(run_capture(command));
    std::string name;
    uint64_t misses = 0;
    while (lines >> name >> misses) expected[name] = misses;
    ASSERT_EQ(expected.size(), policies.size()) << command;
    for (const std::string& policy : policies) {
      SetAssocCache c(geometry(g.size, g.assoc, g.line, policy));
      const uint64_t got = c.replay(trace);
      EXPECT_EQ(got, expected[policy]) << policy << " " << g.size << "/" << g.assoc << "/" << g.line;
      EXPECT_GT(got, 0u);
      EXPECT_LT(got, trace.size());
    }
  }
  std::filesystem::remove(trace_path);
}

// --- The stream fetch sink --------------------------------------------------------------------

template <class Sink>
concept TraversalSink = requires(Sink& s) { s.fetch(Stream::kNode, uint64_t{0}, uint32_t{0}); };
static_assert(TraversalSink<FetchCache>);

TEST(CacheTest, FetchSinkRoutesStreamsStraightToDram) {
  FetchCacheParams p;  // node L1 8 KB / 4 / 64, lists and triangles straight to DRAM
  FetchCache f(p);
  f.fetch(Stream::kNode, 0, 8);     // miss
  f.fetch(Stream::kNode, 8, 8);     // hit (same line)
  f.fetch(Stream::kNode, 64, 8);    // miss
  f.fetch(Stream::kList, 4096, 8);  // one burst
  f.fetch(Stream::kList, 4096, 8);  // again: no cache, one more burst
  f.fetch(Stream::kTriangle, 8192 + 60, 36);  // crosses a burst boundary: two bursts
  f.fetch(Stream::kTriangle, 8192 + 128, 36); // one burst

  const StreamCounters& n = f.stream(Stream::kNode);
  EXPECT_EQ(n.fetches, 3u);
  EXPECT_EQ(n.accesses, 3u);
  EXPECT_EQ(n.hits, 1u);
  EXPECT_EQ(n.misses, 2u);
  EXPECT_EQ(n.dram_bytes, 128u);
  EXPECT_EQ(f.node_l1().accesses(), 3u);  // lists and triangles never touch the L1
  EXPECT_EQ(f.stream(Stream::kList).dram_bytes, 128u);
  EXPECT_EQ(f.stream(Stream::kTriangle).fetches, 2u);
  EXPECT_EQ(f.stream(Stream::kTriangle).accesses, 3u);
  EXPECT_EQ(f.stream(Stream::kTriangle).dram_bytes, 192u);
  EXPECT_EQ(f.dram_bytes_total(), 128u + 128u + 192u);
  EXPECT_EQ(f.data_cache(), nullptr);

  Stats s;
  f.write_stats(s);
  EXPECT_EQ(s.at("l1.accesses").get<uint64_t>(), 3u);
  EXPECT_EQ(s.at("l1.misses").get<uint64_t>(), 2u);
  EXPECT_EQ(s.at("dram.bytes.nodes").get<uint64_t>(), 128u);
  EXPECT_EQ(s.at("dram.bytes.lists").get<uint64_t>(), 128u);
  EXPECT_EQ(s.at("dram.bytes.triangles").get<uint64_t>(), 192u);
  EXPECT_EQ(s.at("dram.bytes.total").get<uint64_t>(), 448u);
  EXPECT_FALSE(s.has("dcache.accesses"));
}

TEST(CacheTest, FetchSinkWithDataCache) {
  FetchCacheParams p;
  p.node_l1 = geometry(1024, 2, 64, "lru");
  p.data_cache = geometry(2048, 2, 32, "fifo");
  FetchCache f(p);
  f.fetch(Stream::kList, 4096, 8);          // miss: 32 B line
  f.fetch(Stream::kList, 4100, 4);          // hit
  f.fetch(Stream::kTriangle, 4096 + 24, 36);  // 4120..4155: lines 4096 (hit) and 4128 (miss)
  f.fetch(Stream::kNode, 0, 8);             // node L1 miss
  f.fetch(Stream::kNode, 4096, 8);          // node L1 miss: the data cache is separate

  EXPECT_EQ(f.stream(Stream::kList).hits, 1u);
  EXPECT_EQ(f.stream(Stream::kList).misses, 1u);
  EXPECT_EQ(f.stream(Stream::kList).dram_bytes, 32u);
  EXPECT_EQ(f.stream(Stream::kTriangle).accesses, 2u);
  EXPECT_EQ(f.stream(Stream::kTriangle).hits, 1u);
  EXPECT_EQ(f.stream(Stream::kTriangle).dram_bytes, 32u);
  EXPECT_EQ(f.stream(Stream::kNode).dram_bytes, 128u);
  ASSERT_NE(f.data_cache(), nullptr);
  EXPECT_EQ(f.data_cache()->accesses(), 4u);
  EXPECT_EQ(f.data_cache()->misses(), 2u);
  EXPECT_EQ(f.dram_bytes_total(), f.node_l1().bytes_from_dram() + f.data_cache()->bytes_from_dram());

  Stats s;
  f.write_stats(s);
  EXPECT_EQ(s.at("dcache.misses").get<uint64_t>(), 2u);
  EXPECT_EQ(s.at("fetch.triangles.accesses").get<uint64_t>(), 2u);
  EXPECT_EQ(s.at("dram.bytes.total").get<uint64_t>(), 192u);
}

TEST(CacheTest, FetchSinkValidationNamesItsKeys) {
  FetchCacheParams p;
  p.data_cache = geometry(8000, 4, 64, "lru");
  try {
    FetchCache f(p);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("dcache.size: 8000", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace rtusim
