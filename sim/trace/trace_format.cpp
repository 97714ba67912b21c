// Trace files: din and bin writers, and the checking reader.
#include "trace/trace_format.h"

#include <cstring>
#include <fstream>
#include <stdexcept>

#include "util/error.h"

namespace rtusim {
namespace {

constexpr size_t kBufferBytes = size_t{1} << 20;

void put_u32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
void put_u64(uint8_t* p, uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
uint32_t get_u32(const uint8_t* p) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
uint64_t get_u64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

}  // namespace

uint64_t trace_checksum(std::span<const uint64_t> addrs) {
  TraceDigest d;
  for (const uint64_t a : addrs) d.add(a);
  return d.checksum;
}

uint64_t fnv1a_bytes(std::span<const uint8_t> bytes, uint64_t h) {
  for (const uint8_t b : bytes) h = (h ^ b) * kFnvPrime;
  return h;
}

uint64_t image_hash(const MemoryImage& image) { return fnv1a_bytes(image.bytes); }

std::string hex64(uint64_t v) {
  char s[17];
  std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(v));
  return s;
}

// ---- writer ----

TraceWriter::TraceWriter(const std::filesystem::path& path, TraceFormat format,
                         const std::string& layout, uint32_t node_bytes, uint64_t scene_hash)
    : path_(path), format_(format), layout_(layout), node_bytes_(node_bytes),
      scene_hash_(scene_hash), buf_(kBufferBytes) {
  if (layout_.empty() || layout_.size() > kMaxLayoutNameBytes)
    throw std::logic_error("trace: layout name '" + layout_ + "' does not fit the bin header");
  file_ = std::fopen(path_.c_str(), "wb");
  if (!file_) throw std::runtime_error("cannot open " + path_.string() + " for writing");
  if (format_ == TraceFormat::kBin) write_header();  // placeholder; finish() rewrites it
}

TraceWriter::~TraceWriter() {
  if (file_) std::fclose(file_);
}

void TraceWriter::append_din(uint64_t addr) {
  static constexpr char kHex[] = "0123456789abcdef";
  char digits[16];
  int n = 0;
  do {
    digits[n++] = kHex[addr & 15];
    addr >>= 4;
  } while (addr != 0);
  uint8_t* p = buf_.data() + used_;
  *p++ = '0';
  *p++ = ' ';
  while (n > 0) *p++ = static_cast<uint8_t>(digits[--n]);
  *p++ = '\n';
  used_ = static_cast<size_t>(p - buf_.data());
}

void TraceWriter::flush_buffer() {
  if (used_ == 0) return;
  if (std::fwrite(buf_.data(), 1, used_, file_) != used_)
    throw std::runtime_error("cannot write " + path_.string());
  payload_bytes_ += used_;
  used_ = 0;
}

void TraceWriter::write_header() {
  std::vector<uint8_t> h(kBinFixedHeaderBytes + layout_.size());
  std::memcpy(h.data(), kBinMagic, 8);
  put_u32(&h[8], kBinVersion);
  put_u32(&h[12], node_bytes_);
  put_u64(&h[16], scene_hash_);
  put_u64(&h[24], digest_.count);
  put_u64(&h[32], digest_.checksum);
  put_u64(&h[40], payload_bytes_);
  put_u32(&h[48], static_cast<uint32_t>(layout_.size()));
  std::memcpy(&h[52], layout_.data(), layout_.size());
  if (std::fseek(file_, 0, SEEK_SET) != 0 || std::fwrite(h.data(), 1, h.size(), file_) != h.size())
    throw std::runtime_error("cannot write " + path_.string());
}

void TraceWriter::finish() {
  flush_buffer();
  if (format_ == TraceFormat::kBin) write_header();
  const bool ok = std::fflush(file_) == 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!ok || !closed) throw std::runtime_error("cannot write " + path_.string());
}

// ---- reader ----

TraceReader::TraceReader(const std::filesystem::path& path) : name_(path.string()) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot open trace file");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) fail("cannot read trace file");
  in.seekg(0);
  data_.resize(static_cast<size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(data_.data()), size))
    fail("cannot read trace file");
  if (data_.size() >= 8 && std::memcmp(data_.data(), kBinMagic, 8) == 0) {
    parse_bin_header();
  } else if (!data_.empty() && (data_[0] == '0' || data_[0] == '1' || data_[0] == '2')) {
    header_.format = TraceFormat::kDin;  // count filled in by decode()
  } else if (data_.size() < 8 && !data_.empty() &&
             std::memcmp(data_.data(), kBinMagic, data_.size()) == 0) {
    fail("truncated: " + std::to_string(data_.size()) + " bytes, shorter than the bin header");
  } else if (data_.empty()) {
    fail("empty file (neither a bin nor a din trace)");
  } else {
    fail("bad magic: not an RTUTRACE bin trace, and not a din trace (lines '0 <hex address>')");
  }
}

void TraceReader::fail(const std::string& what) const { throw InputError(name_ + ": " + what); }

void TraceReader::parse_bin_header() {
  header_.format = TraceFormat::kBin;
  if (data_.size() < kBinFixedHeaderBytes)
    fail("truncated: " + std::to_string(data_.size()) + " bytes, shorter than the " +
         std::to_string(kBinFixedHeaderBytes) + "-byte bin header");
  const uint8_t* p = data_.data();
  header_.version = get_u32(p + 8);
  if (header_.version != kBinVersion)
    fail("unsupported bin trace version " + std::to_string(header_.version) + " (this build reads " +
         std::to_string(kBinVersion) + ")");
  header_.node_bytes = get_u32(p + 12);
  header_.scene_hash = get_u64(p + 16);
  header_.count = get_u64(p + 24);
  header_.checksum = get_u64(p + 32);
  header_.payload_bytes = get_u64(p + 40);
  const uint32_t name_len = get_u32(p + 48);
  if (name_len == 0 || name_len > kMaxLayoutNameBytes)
    fail("bad header: layout name length " + std::to_string(name_len));
  if (data_.size() < kBinFixedHeaderBytes + uint64_t{name_len})
    fail("truncated: the header's layout name is cut off");
  header_.layout.assign(reinterpret_cast<const char*>(p + kBinFixedHeaderBytes), name_len);
  payload_offset_ = kBinFixedHeaderBytes + name_len;
  const uint64_t have = data_.size() - payload_offset_;
  if (have < header_.payload_bytes)
    fail("truncated: payload has " + std::to_string(have) + " of " +
         std::to_string(header_.payload_bytes) + " bytes");
  if (have > header_.payload_bytes)
    fail(std::to_string(have - header_.payload_bytes) + " bytes of trailing data after the payload");
  // Every record takes 1..10 bytes.
  if (header_.count > header_.payload_bytes || header_.payload_bytes > 10 * header_.count)
    fail("bad header: " + std::to_string(header_.count) + " records cannot take " +
         std::to_string(header_.payload_bytes) + " payload bytes");
}

std::vector<uint64_t> TraceReader::decode() const {
  return header_.format == TraceFormat::kBin ? decode_bin() : decode_din();
}

std::vector<uint64_t> TraceReader::decode_bin() const {
  std::vector<uint64_t> out(header_.count);
  const uint8_t* p = data_.data() + payload_offset_;
  const uint8_t* const end = p + header_.payload_bytes;
  uint64_t prev = 0, h = kFnvOffset;
  for (uint64_t i = 0; i < header_.count; ++i) {
    uint64_t z = 0;
    int shift = 0;
    for (;;) {
      if (p == end) fail("truncated: payload ends inside record " + std::to_string(i) + " of " +
                         std::to_string(header_.count));
      const uint8_t b = *p++;
      if (shift == 63 && b > 1) fail("bad varint in record " + std::to_string(i));
      z |= uint64_t{b & 0x7fu} << shift;
      if (!(b & 0x80)) break;
      shift += 7;
      if (shift > 63) fail("bad varint in record " + std::to_string(i));
    }
    prev += (z >> 1) ^ (0 - (z & 1));  // zig-zag back to the signed difference
    out[i] = prev;
    h = (h ^ prev) * kFnvPrime;
  }
  if (p != end)
    fail("payload holds " + std::to_string(end - p) + " bytes beyond the header's " +
         std::to_string(header_.count) + " records");
  if (h != header_.checksum)
    fail("checksum mismatch: header " + hex64(header_.checksum) + ", addresses " + hex64(h));
  return out;
}

std::vector<uint64_t> TraceReader::decode_din() const {
  std::vector<uint64_t> out;
  const char* p = reinterpret_cast<const char*>(data_.data());
  const char* const end = p + data_.size();
  uint64_t line = 0;
  while (p < end) {
    ++line;
    const char* eol = static_cast<const char*>(std::memchr(p, '\n', size_t(end - p)));
    if (!eol) eol = end;
    const char* q = p;
    p = eol + 1;
    if (q < eol && eol[-1] == '\r') --eol;
    while (q < eol && (*q == ' ' || *q == '\t')) ++q;
    if (q == eol) continue;  // blank line
    if (!(*q == '0' || *q == '1' || *q == '2') || q + 1 == eol || (q[1] != ' ' && q[1] != '\t'))
      fail("line " + std::to_string(line) + ": expected '<label 0-2> <hex address>'");
    q += 2;
    while (q < eol && (*q == ' ' || *q == '\t')) ++q;
    if (q + 1 < eol && q[0] == '0' && (q[1] == 'x' || q[1] == 'X')) q += 2;
    uint64_t a = 0;
    int digits = 0;
    for (; q < eol && *q != ' ' && *q != '\t'; ++q, ++digits) {
      const char c = *q;
      int v;
      if (c >= '0' && c <= '9') v = c - '0';
      else if (c >= 'a' && c <= 'f') v = c - 'a' + 10;
      else if (c >= 'A' && c <= 'F') v = c - 'A' + 10;
      else fail("line " + std::to_string(line) + ": '" + std::string(1, c) + "' is not a hex digit");
      a = (a << 4) | static_cast<uint64_t>(v);
    }
    if (digits == 0 || digits > 16)
      fail("line " + std::to_string(line) + ": expected a hex address of 1 to 16 digits");
    out.push_back(a);
  }
  return out;
}

}  // namespace rtusim
