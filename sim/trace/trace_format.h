// Node-fetch address traces: the Dinero IV "din" text format and rtusim's compact "bin" format,
// a writer for each and one reader for both.
//
// din (Dinero IV traditional format): one line per fetch, "0 <address>\n", the address in
// lowercase hex without 0x ("0 1a40"). Label 0 = data read. No header, so no layout, node size or
// checksum; the reader accepts any label 0/1/2 line and blank lines.
//
// bin (little endian throughout):
//   offset  size  field
//        0     8  magic "RTUTRACE"
//        8     4  u32 version (kBinVersion = 1)
//       12     4  u32 node_bytes: bytes read per fetch (8 for dfl/odfl, 12 for subtree)
//       16     8  u64 scene_hash: FNV-1a 64 over the memory image's bytes (nodes, lists,
//                 triangles), so a trace names the exact tree it was taken from
//       24     8  u64 count: records (fetches)
//       32     8  u64 checksum: trace_checksum() of the addresses, in order
//       40     8  u64 payload_bytes: bytes of the encoded addresses after the header
//       48     4  u32 layout_len: length of the layout name (1..64)
//       52     L  layout name ("dfl", "odfl", "subtree"), no terminator
//     52+L     P  payload: per record, the signed difference from the previous address
//                 (the first from 0), zig-zag mapped (d >= 0 -> 2d, d < 0 -> -2d - 1) and written
//                 as an unsigned LEB128 varint (7 bits per byte, low first, high bit = more).
//                 Arithmetic is modulo 2^64. A depth-first step to the next 8-byte node is the
//                 one byte 0x10.
// The file ends exactly after the payload.
//
// Checksum (trace_checksum): an FNV-1a 64 variant over 64-bit words: h = 0xcbf29ce484222325;
// per address a: h = (h ^ a) * 0x100000001b3. Each step is a bijection of h, so any single
// changed, lost or added address changes the result. `rtusim regress` records it as
// trace.node_stream.checksum (16 lowercase hex digits).
#pragma once
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "layout/memory_image.h"

namespace rtusim {

// kDinSized: din lines with a third field, the fetch's bytes in hex ("0 1a40 c"): Dinero IV's
// extended din input, so a tool that honours sizes counts a node straddling two lines twice.
// Closes a FILE owned by a unique_ptr (so a constructor that throws still closes it).
struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

enum class TraceFormat { kDin, kDinSized, kBin };

inline constexpr char kBinMagic[8] = {'R', 'T', 'U', 'T', 'R', 'A', 'C', 'E'};
inline constexpr uint32_t kBinVersion = 1;
inline constexpr uint32_t kBinFixedHeaderBytes = 52;
inline constexpr uint32_t kMaxLayoutNameBytes = 64;

inline constexpr uint64_t kFnvOffset = 0xcbf29ce484222325ull;
inline constexpr uint64_t kFnvPrime = 0x100000001b3ull;

// Count and checksum of an address stream, updated one address at a time.
struct TraceDigest {
  uint64_t count = 0;
  uint64_t checksum = kFnvOffset;
  void add(uint64_t addr) {
    ++count;
    checksum = (checksum ^ addr) * kFnvPrime;
  }
};

uint64_t trace_checksum(std::span<const uint64_t> addrs);
// FNV-1a 64 over bytes (the scene hash of a bin trace).
uint64_t fnv1a_bytes(std::span<const uint8_t> bytes, uint64_t h = kFnvOffset);
// The scene hash of an image: FNV-1a 64 over all its bytes.
uint64_t image_hash(const MemoryImage& image);
// 16 lowercase hex digits.
std::string hex64(uint64_t v);

// Writes one trace file; append() per fetch, then finish(). Throws InputError on a write
// failure (a full disk, a file size limit), naming `name` (default: the path; a temporary
// file's writer names the file it becomes).
class TraceWriter {
 public:
  // `layout`, `node_bytes` and `scene_hash` go in the bin header (ignored by din).
  TraceWriter(const std::filesystem::path& path, TraceFormat format, const std::string& layout,
              uint32_t node_bytes, uint64_t scene_hash, std::string name = "");
  ~TraceWriter();
  TraceWriter(const TraceWriter&) = delete;
  TraceWriter& operator=(const TraceWriter&) = delete;

  void append(uint64_t addr) {
    if (buf_.size() - used_ < kMaxRecordBytes) flush_buffer();
    digest_.add(addr);
    if (format_ == TraceFormat::kBin) {
      const uint64_t d = addr - prev_;
      prev_ = addr;
      uint64_t z = (d << 1) ^ (0 - (d >> 63));  // zig-zag of the signed difference
      while (z >= 0x80) {
        buf_[used_++] = static_cast<uint8_t>(z | 0x80);
        z >>= 7;
      }
      buf_[used_++] = static_cast<uint8_t>(z);
    } else {
      append_din(addr);
    }
  }
  // Completes the file (the bin header's count, checksum and payload size). Call once.
  void finish();
  const TraceDigest& digest() const { return digest_; }

 private:
  // "0 " + 16 hex digits + " " + 8 hex digits + "\n"; a varint takes <= 10.
  static constexpr size_t kMaxRecordBytes = 28;
  void append_din(uint64_t addr);
  void flush_buffer();
  void write_header();

  std::filesystem::path path_;
  std::string name_;  // in messages
  TraceFormat format_;
  std::string layout_;
  uint32_t node_bytes_;
  uint64_t scene_hash_;
  FilePtr file_;
  std::vector<uint8_t> buf_;
  size_t used_ = 0;
  uint64_t prev_ = 0;
  uint64_t payload_bytes_ = 0;
  TraceDigest digest_;
};

// What a trace file says about itself (din: only format and, once read, count).
struct TraceHeader {
  TraceFormat format = TraceFormat::kDin;
  uint32_t version = 0;
  uint32_t node_bytes = 0;  // 0 = unknown (din)
  uint64_t scene_hash = 0;
  uint64_t count = 0;
  uint64_t checksum = 0;
  uint64_t payload_bytes = 0;
  std::string layout;  // "" for din
};

// Largest bytes one fetch may read (bin node_bytes, din size field): a header claiming more is
// rejected rather than replayed as millions of line accesses per record.
inline constexpr uint32_t kMaxFetchBytes = 4096;

// Reads a bin or din trace (told apart by the magic) in bounded memory: the constructor opens
// the file and checks the header against the file's size; next() decodes the records a chunk at
// a time through a fixed buffer, and checks count, payload size and checksum (bin) when the end
// is reached. Every error is an InputError "FILE: what is wrong" (truncated, bad magic,
// unsupported version, checksum mismatch, bad din line N ...).
//
// din lines are "<label 0-2> <hex address>" (Dinero IV's traditional format) or
// "<label> <hex address> <hex size>" (its extended format, the bytes the access reads).
class TraceReader {
 public:
  explicit TraceReader(const std::filesystem::path& path);
  TraceReader(const TraceReader&) = delete;
  TraceReader& operator=(const TraceReader&) = delete;

  const TraceHeader& header() const { return header_; }
  // Decodes up to `max_records` records into `addrs` (replaced). `sizes` is left empty unless
  // a din line in the chunk has a size field; then it holds one size per record (0 = none).
  // Returns false, with both empty, once every record was read and the trailer checks passed.
  bool next(std::vector<uint64_t>& addrs, std::vector<uint32_t>& sizes, size_t max_records);
  // Every address, in order (reads the file again from the start; for tests and benchmarks).
  std::vector<uint64_t> decode() const;
  // Throws InputError "FILE: what" (for what a reader of its records finds wrong in them).
  [[noreturn]] void fail(const std::string& what) const;

 private:
  void parse_bin_header(uint64_t file_bytes);
  // Keeps the unread bytes and appends more from the file (bin: never past the payload).
  // Returns false when nothing was left to read.
  bool refill();
  template <bool kChecked>
  uint64_t read_varint(const uint8_t*& p, const uint8_t* end, uint64_t record) const;
  bool next_bin(std::vector<uint64_t>& addrs, size_t max_records);
  bool next_din(std::vector<uint64_t>& addrs, std::vector<uint32_t>& sizes, size_t max_records);
  void din_line(const char* q, const char* eol, std::vector<uint64_t>& addrs,
                std::vector<uint32_t>& sizes);

  std::filesystem::path path_;
  std::string name_;
  FilePtr file_;
  std::vector<uint8_t> buf_;
  size_t pos_ = 0, end_ = 0;     // unread bytes: buf_[pos_, end_)
  uint64_t file_left_ = 0;       // bytes still to read from the file (bin: of the payload)
  uint64_t records_ = 0;         // records decoded so far
  uint64_t prev_ = 0;            // bin: the previous address
  uint64_t hash_ = kFnvOffset;   // bin: running checksum
  uint64_t line_ = 0;            // din: lines read
  bool done_ = false;
  TraceHeader header_;
};

}  // namespace rtusim
