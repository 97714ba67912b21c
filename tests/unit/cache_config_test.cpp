// Cache config keys: l1.* and dcache.* read through ConfigReader, errors naming key and file.
#include <string>

#include <gtest/gtest.h>

#include "app/run_config.h"
#include "config/config_reader.h"
#include "mem/l1_params.h"
#include "util/error.h"

namespace rtusim {
namespace {

// The caches of a run as RunConfig derives them from the l1.* and dcache.* keys.
FetchCacheParams read_fetch_cache_params(ConfigReader& r) {
  RunConfig c;
  c.l1 = read_node_l1_config(r);
  c.dcache = read_dcache_config(r);
  return c.fetch_caches();
}

std::string read_error(const std::string& toml) {
  ConfigReader r = ConfigReader::from_string(toml, "test.toml");
  try {
    read_fetch_cache_params(r);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CacheConfigTest, ReadsL1AndDataCache) {
  ConfigReader r = ConfigReader::from_string(
      "[l1]\nsize = 16384\nassoc = 8\nline = 32\npolicy = \"tree-plru\"\n"
      "[dcache]\nenable = true\nsize = 4096\npolicy = \"random\"\nseed = 7\n",
      "test.toml");
  const FetchCacheParams p = read_fetch_cache_params(r);
  EXPECT_EQ(p.node_l1.size_bytes, 16384u);
  EXPECT_EQ(p.node_l1.assoc, 8u);
  EXPECT_EQ(p.node_l1.line_bytes, 32u);
  EXPECT_EQ(p.node_l1.policy, "tree-plru");
  ASSERT_TRUE(p.data_cache.has_value());
  EXPECT_EQ(p.data_cache->size_bytes, 4096u);
  EXPECT_EQ(p.data_cache->assoc, 4u);  // default
  EXPECT_EQ(p.data_cache->seed, 7u);
  EXPECT_NO_THROW(r.reject_unknown_keys());
}

TEST(CacheConfigTest, DefaultsAreThePaperCache) {
  ConfigReader r = ConfigReader::from_string("", "test.toml");
  const FetchCacheParams p = read_fetch_cache_params(r);
  EXPECT_EQ(p.node_l1.size_bytes, 8192u);
  EXPECT_EQ(p.node_l1.assoc, 4u);
  EXPECT_EQ(p.node_l1.line_bytes, 64u);
  EXPECT_EQ(p.node_l1.policy, "lru");
  EXPECT_FALSE(p.data_cache.has_value());
}

TEST(CacheConfigTest, FullAssociativityIsOneSet) {
  ConfigReader r = ConfigReader::from_string(
      "[l1]\nsize = 4096\nassoc = \"full\"\nline = 32\n[dcache]\nenable = true\nsize = 2048\n",
      "test.toml");
  r.apply_override("dcache.assoc=full");  // a bare word from --set
  const FetchCacheParams p = read_fetch_cache_params(r);
  EXPECT_EQ(p.node_l1.assoc, 128u);
  ASSERT_TRUE(p.data_cache.has_value());
  EXPECT_EQ(p.data_cache->assoc, 32u);
  // The effective config keeps the word.
  EXPECT_EQ(r.effective()["l1"]["assoc"].value<std::string>(), "full");
  EXPECT_EQ(r.effective()["dcache"]["assoc"].value<std::string>(), "full");
  EXPECT_EQ(read_error("[l1]\nassoc = \"half\"\n"),
            "test.toml:2: l1.assoc: expected an integer or \"full\", got \"half\"");
  // One set smaller than a line is still the geometry check's error.
  EXPECT_NE(read_error("[l1]\nsize = 32\nassoc = \"full\"\n").find("l1.size"), std::string::npos);
}

TEST(CacheConfigTest, ErrorsNameKeyAndFile) {
  EXPECT_EQ(read_error("[l1]\nsize = 8000\n"),
            "test.toml:2: l1.size: 8000 is not a multiple of l1.line x l1.assoc (256)");
  // A check across keys names the line of the key involved that the file sets.
  EXPECT_EQ(read_error("[l1]\n\nassoc = 256\n"),
            "test.toml:3: l1.size: 8192 is smaller than l1.line x l1.assoc (16384)");
  EXPECT_NE(read_error("[l1]\npolicy = \"mru\"\n").find("l1.policy"), std::string::npos);
  EXPECT_NE(read_error("[l1]\nassoc = 0\n").find("l1.assoc"), std::string::npos);
  EXPECT_EQ(read_error("[dcache]\nline = 48\n"), "test.toml:2: dcache.line: 48 must be a power of two >= 4");
}

}  // namespace
}  // namespace rtusim
