// The registry of built RTL L1 combinations: it lists exactly the Verilated models, finds them
// by cache parameters, names every key of an unbuilt combination in its error, and its fixed
// MSHR count is the models'.
#include <gtest/gtest.h>

#include <string>

#include "rtl/rtl_l1_registry.h"
#include "rtl_l1_harness.h"
#include "util/error.h"

namespace rtusim::rtltest {
namespace {

TEST(RtlL1Registry, ListsTheBuiltModelsIncludingTheDefault) {
  ASSERT_FALSE(rtl_l1_builds().empty());
  EXPECT_EQ(rtl_l1_builds().size(), cpp_model_names().size());
  for (const RtlL1Build& b : rtl_l1_builds()) EXPECT_TRUE(make_cpp_model(std::string(b.model)));
  const RtlL1Build& d = rtl_l1_build(CacheParams{});
  EXPECT_EQ(d.size_bytes, 8192u);
  EXPECT_EQ(d.assoc, 4u);
  EXPECT_EQ(d.line_bytes, 64u);
  EXPECT_EQ(d.policy, "lru");
  EXPECT_EQ(d.model, "Vl1_8192_4_64_lru");
}

TEST(RtlL1Registry, UnbuiltCombinationIsAnInputErrorListingTheBuiltOnes) {
  CacheParams p;
  p.size_bytes = 32768;
  p.policy = "tree-plru";
  EXPECT_EQ(find_rtl_l1_build(p), nullptr);
  try {
    rtl_l1_build(p);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("l1.model = rtl: no RTL build for l1.size=32768, l1.assoc=4, l1.line=64, "
                      "l1.policy=tree-plru (built: ", 0), 0u) << m;
    EXPECT_NE(m.find("8192/4/64/lru"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos);
  }
  p.size_bytes = 8192;
  p.policy = "fifo";
  EXPECT_THROW(rtl_l1_build(p), InputError);
}

TEST(RtlL1Registry, EveryBuildHasTheFixedMshrCount) {
  for (const RtlL1Build& b : rtl_l1_builds()) {
    SCOPED_TRACE(std::string(b.model));
    auto m = make_cpp_model(std::string(b.model));
    ASSERT_TRUE(m);
    Inputs in;
    in.req_valid = true;
    uint32_t accepted = 0;
    for (uint32_t i = 0; i < RtlL1Build::kMshrs + 1; ++i) {  // primaries on distinct lines
      in.req_addr = uint64_t{b.size_bytes} * (i + 1);
      in.req_id = i;
      m->drive(in);
      accepted += m->outputs().req_ready ? 1 : 0;
      m->posedge();
    }
    EXPECT_EQ(accepted, RtlL1Build::kMshrs) << "the last primary waits for an MSHR";
    EXPECT_EQ(m->outputs().mshrs_busy, RtlL1Build::kMshrs);
    in.req_addr = b.size_bytes;  // pending: merges
    m->drive(in);
    EXPECT_TRUE(m->outputs().req_ready && m->outputs().req_merged) << "merges go on";
  }
}

}  // namespace
}  // namespace rtusim::rtltest
