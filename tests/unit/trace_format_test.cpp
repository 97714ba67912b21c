// Trace files: bin and din round trips, the bin encoding, and the reader's checks.
#include "trace/trace_format.h"

#include <filesystem>
#include <fstream>
#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "util/error.h"

namespace rtusim {
namespace {
namespace fs = std::filesystem;

class TraceFormatTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rtusim_trace_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, TraceFormat f, const std::vector<uint64_t>& addrs) {
    const fs::path p = dir_ / name;
    TraceWriter w(p, f, "odfl", 8, 0x1234);
    for (const uint64_t a : addrs) w.append(a);
    w.finish();
    EXPECT_EQ(w.digest().count, addrs.size());
    EXPECT_EQ(w.digest().checksum, trace_checksum(addrs));
    return p;
  }
  std::vector<uint8_t> bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  void put(const fs::path& p, const std::vector<uint8_t>& b) {
    std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), b.size());
  }
  // The reader's error for `p`, "" if it reads.
  std::string error_of(const fs::path& p) {
    try {
      TraceReader(p).decode();
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
};

std::vector<uint64_t> sample_addresses() {
  std::mt19937_64 rng(7);
  std::vector<uint64_t> a = {0, 8, 16, 0x2cf60, 0, ~uint64_t{0}, 0, uint64_t{1} << 63, 5, 4};
  uint64_t x = 0;
  for (int i = 0; i < 100000; ++i) {
    const uint64_t r = rng() % 100;
    x = r < 70 ? x + 8 : r < 90 ? (rng() % 4096) * 8 : rng();
    a.push_back(x);
  }
  return a;
}

TEST_F(TraceFormatTest, BinRoundTripKeepsEveryAddressAndTheHeader) {
  const auto addrs = sample_addresses();
  const fs::path p = write("a.bin", TraceFormat::kBin, addrs);
  TraceReader r(p);
  EXPECT_EQ(r.header().format, TraceFormat::kBin);
  EXPECT_EQ(r.header().version, kBinVersion);
  EXPECT_EQ(r.header().layout, "odfl");
  EXPECT_EQ(r.header().node_bytes, 8u);
  EXPECT_EQ(r.header().scene_hash, 0x1234u);
  EXPECT_EQ(r.header().count, addrs.size());
  EXPECT_EQ(r.decode(), addrs);
}

TEST_F(TraceFormatTest, DinRoundTripAndLineFormat) {
  const std::vector<uint64_t> addrs = {0, 0x2cf60, 0xabcdef0123456789ull, 8};
  const fs::path p = write("a.din", TraceFormat::kDin, addrs);
  const auto b = bytes(p);
  EXPECT_EQ(std::string(b.begin(), b.end()), "0 0\n0 2cf60\n0 abcdef0123456789\n0 8\n");
  TraceReader r(p);
  EXPECT_EQ(r.header().format, TraceFormat::kDin);
  EXPECT_EQ(r.decode(), addrs);
  EXPECT_EQ(TraceReader(write("b.din", TraceFormat::kDin, sample_addresses())).decode(),
            sample_addresses());
}

TEST_F(TraceFormatTest, BinEncodesANextNodeStepInOneByte) {
  const fs::path p = write("steps.bin", TraceFormat::kBin, {0, 8, 16, 8});
  const auto b = bytes(p);
  ASSERT_EQ(b.size(), kBinFixedHeaderBytes + 4 + 4);  // "odfl" and one byte per record
  EXPECT_EQ(std::vector<uint8_t>(b.end() - 4, b.end()), (std::vector<uint8_t>{0x00, 0x10, 0x10, 0x0f}));
}

TEST_F(TraceFormatTest, EmptyTraceIsValid) {
  const fs::path p = write("empty.bin", TraceFormat::kBin, {});
  EXPECT_TRUE(TraceReader(p).decode().empty());
}

TEST_F(TraceFormatTest, ReaderRejectsDamagedFilesNamingThem) {
  const fs::path p = write("good.bin", TraceFormat::kBin, sample_addresses());
  const auto good = bytes(p);

  auto b = good;
  b.resize(b.size() - 1);
  put(dir_ / "trunc.bin", b);
  EXPECT_NE(error_of(dir_ / "trunc.bin").find("trunc.bin: truncated"), std::string::npos);

  b.assign(good.begin(), good.begin() + 20);
  put(dir_ / "short.bin", b);
  EXPECT_NE(error_of(dir_ / "short.bin").find("short.bin: truncated"), std::string::npos);

  b = good;
  b.back() ^= 0x02;
  put(dir_ / "flip.bin", b);
  EXPECT_NE(error_of(dir_ / "flip.bin").find("flip.bin: checksum mismatch"), std::string::npos);

  b = good;
  b[0] = 'X';
  put(dir_ / "magic.bin", b);
  EXPECT_NE(error_of(dir_ / "magic.bin").find("magic.bin: bad magic"), std::string::npos);

  b = good;
  b[8] = 9;  // version
  put(dir_ / "version.bin", b);
  EXPECT_NE(error_of(dir_ / "version.bin").find("version.bin: unsupported bin trace version 9"),
            std::string::npos);

  b = good;
  b.push_back(0);
  put(dir_ / "long.bin", b);
  EXPECT_NE(error_of(dir_ / "long.bin").find("long.bin: 1 bytes of trailing data"), std::string::npos);

  b = good;
  b[24] ^= 1;  // count
  put(dir_ / "count.bin", b);
  EXPECT_NE(error_of(dir_ / "count.bin").find("count.bin: "), std::string::npos);

  put(dir_ / "bad.din", {'0', ' ', '1', '0', '\n', '0', ' ', 'g', '\n'});
  EXPECT_NE(error_of(dir_ / "bad.din").find("bad.din: line 2"), std::string::npos);
  EXPECT_NE(error_of(dir_ / "none.bin").find("none.bin: cannot open"), std::string::npos);
}

// Streaming: any chunk size returns the same addresses as one decode, and a trace larger than
// the reader's 1 MiB buffer crosses buffer boundaries inside records (multi-byte varints).
TEST_F(TraceFormatTest, StreamingInChunksMatchesWholeDecode) {
  std::vector<uint64_t> addrs = sample_addresses();
  std::mt19937_64 rng(11);
  for (int i = 0; i < 300000; ++i) addrs.push_back(rng());  // ~10 bytes each: > 1 MiB payload
  for (const TraceFormat f : {TraceFormat::kBin, TraceFormat::kDin, TraceFormat::kDinSized}) {
    if (f == TraceFormat::kDinSized)  // a sized access may not run past 2^64 (the writer's 8 bytes)
      for (uint64_t& a : addrs) a = std::min(a, ~uint64_t{0} - 7);
    const fs::path p = write("s" + std::to_string(int(f)), f, addrs);
    for (const size_t chunk : {size_t{1}, size_t{7}, size_t{65536}, size_t{1} << 22}) {
      TraceReader r(p);
      std::vector<uint64_t> got, part;
      std::vector<uint32_t> sizes;
      while (r.next(part, sizes, chunk)) {
        ASSERT_LE(part.size(), chunk);
        if (f == TraceFormat::kDinSized) {
          ASSERT_EQ(sizes.size(), part.size());
          for (const uint32_t s : sizes) ASSERT_EQ(s, 8u);  // the writer's node_bytes
        } else {
          ASSERT_TRUE(sizes.empty());
        }
        got.insert(got.end(), part.begin(), part.end());
        if (chunk == 1 && got.size() > 2000) break;  // one-record chunks: the start is enough
      }
      if (chunk == 1) {
        ASSERT_TRUE(std::equal(got.begin(), got.end(), addrs.begin()));
        continue;
      }
      EXPECT_EQ(got, addrs) << int(f) << " chunk " << chunk;
      EXPECT_EQ(r.header().count, addrs.size());
    }
  }
}

// A din line may carry Dinero IV's size field; lines with and without one mix.
TEST_F(TraceFormatTest, DinSizeFieldIsReadPerLine) {
  put(dir_ / "sized.din", {'0', ' ', '4', '0', ' ', 'c', '\n', '2', ' ', '8', '0', '\n'});
  TraceReader r(dir_ / "sized.din");
  std::vector<uint64_t> a;
  std::vector<uint32_t> s;
  ASSERT_TRUE(r.next(a, s, 100));
  EXPECT_EQ(a, (std::vector<uint64_t>{0x40, 0x80}));
  EXPECT_EQ(s, (std::vector<uint32_t>{12, 0}));
  EXPECT_FALSE(r.next(a, s, 100));
  // The writer's sized lines: "0 <address> <node bytes>", hex.
  TraceWriter w(dir_ / "w.din", TraceFormat::kDinSized, "subtree", 12, 0);
  w.append(0x1a40);
  w.finish();
  const auto b = bytes(dir_ / "w.din");
  EXPECT_EQ(std::string(b.begin(), b.end()), "0 1a40 c\n");
}

// Header sanity that is not covered by the checksum, and unprintable bytes in messages.
TEST_F(TraceFormatTest, NodeSizeAndUnprintableBytesGiveClearErrors) {
  const fs::path p = write("n.bin", TraceFormat::kBin, {0, 8});
  auto b = bytes(p);
  b[12] = 0xff, b[13] = 0xff, b[14] = 0xff, b[15] = 0x7f;  // node_bytes = 2^31 - 1
  put(dir_ / "huge.bin", b);
  EXPECT_NE(error_of(dir_ / "huge.bin").find("node size 2147483647 bytes"), std::string::npos);
  put(dir_ / "nul.din", {'0', ' ', '1', 0, '2', '\n'});
  const std::string e = error_of(dir_ / "nul.din");
  EXPECT_NE(e.find("line 1: '\\x00' is not a hex digit"), std::string::npos) << e;
  EXPECT_EQ(e.find('\0'), std::string::npos);
  EXPECT_NE(error_of(dir_).find("is a directory"), std::string::npos);
}

// A rejected trace closes its file (the constructor throws after opening it): ten thousand
// rejections in one process must not run out of file descriptors.
TEST_F(TraceFormatTest, RejectedTracesCloseTheirFiles) {
  put(dir_ / "bad.bin", {'R', 'T', 'U', 'T', 'R', 'A', 'C', 'E', 9, 0, 0, 0});
  for (int i = 0; i < 10000; ++i)
    ASSERT_NE(error_of(dir_ / "bad.bin").find("bad.bin: truncated"), std::string::npos) << i;
  EXPECT_EQ(error_of(dir_ / "none.bin").find("Too many open files"), std::string::npos);
}

// Differences of every magnitude, so records of every varint length (1 to 10 bytes) follow one
// another in no pattern, read in chunks that end inside the reader's 64-byte blocks.
TEST_F(TraceFormatTest, BinDecodesEveryRecordLengthInAnyOrder) {
  std::mt19937_64 rng(5);
  std::vector<uint64_t> addrs;
  uint64_t x = 0;
  for (int i = 0; i < 200000; ++i) {
    const uint64_t d = rng() >> (rng() % 64);
    x += (rng() & 1) ? d : 0 - d;
    addrs.push_back(x);
  }
  const fs::path p = write("lengths.bin", TraceFormat::kBin, addrs);
  for (const size_t chunk : {size_t{5}, size_t{63}, size_t{4096}}) {
    TraceReader r(p);
    std::vector<uint64_t> got, part;
    std::vector<uint32_t> sizes;
    while (r.next(part, sizes, chunk)) got.insert(got.end(), part.begin(), part.end());
    EXPECT_EQ(got, addrs) << "chunk " << chunk;
  }
}

TEST_F(TraceFormatTest, ChecksumSeesOrderAndEveryAddress) {
  EXPECT_NE(trace_checksum(std::vector<uint64_t>{1, 2}), trace_checksum(std::vector<uint64_t>{2, 1}));
  EXPECT_NE(trace_checksum(std::vector<uint64_t>{0}), trace_checksum(std::vector<uint64_t>{}));
  EXPECT_NE(trace_checksum(std::vector<uint64_t>{0, 0}), trace_checksum(std::vector<uint64_t>{0}));
  EXPECT_EQ(hex64(0xabc), "0000000000000abc");
}

}  // namespace
}  // namespace rtusim
