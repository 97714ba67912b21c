// Trace files: din and bin writers, and the checking reader.
#include "trace/trace_format.h"

#include <algorithm>
#include <cerrno>
#include <bit>
#include <cstring>
#include <stdexcept>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

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
                         const std::string& layout, uint32_t node_bytes, uint64_t scene_hash,
                         std::string name)
    : path_(path), name_(name.empty() ? path.string() : std::move(name)), format_(format),
      layout_(layout), node_bytes_(node_bytes),
      scene_hash_(scene_hash), buf_(kBufferBytes) {
  if (layout_.empty() || layout_.size() > kMaxLayoutNameBytes)
    throw std::logic_error("trace: layout name '" + layout_ + "' does not fit the bin header");
  file_.reset(std::fopen(path_.c_str(), "wb"));
  if (!file_)
    throw InputError(name_ + ": cannot open for writing (" + std::strerror(errno) + ")");
  if (format_ == TraceFormat::kBin) write_header();  // placeholder; finish() rewrites it
}

TraceWriter::~TraceWriter() = default;

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
  if (format_ == TraceFormat::kDinSized) {
    uint32_t size = node_bytes_;
    do {
      digits[n++] = kHex[size & 15];
      size >>= 4;
    } while (size != 0);
    *p++ = ' ';
    while (n > 0) *p++ = static_cast<uint8_t>(digits[--n]);
  }
  *p++ = '\n';
  used_ = static_cast<size_t>(p - buf_.data());
}

void TraceWriter::flush_buffer() {
  if (used_ == 0) return;
  if (std::fwrite(buf_.data(), 1, used_, file_.get()) != used_)
    throw InputError(name_ + ": cannot write (" + std::strerror(errno) + ")");
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
  if (std::fseek(file_.get(), 0, SEEK_SET) != 0 || std::fwrite(h.data(), 1, h.size(), file_.get()) != h.size())
    throw InputError(name_ + ": cannot write (" + std::strerror(errno) + ")");
}

void TraceWriter::finish() {
  flush_buffer();
  if (format_ == TraceFormat::kBin) write_header();
  const bool ok = std::fflush(file_.get()) == 0;
  const bool closed = std::fclose(file_.release()) == 0;
  if (!ok || !closed) throw InputError(name_ + ": cannot write (" + std::strerror(errno) + ")");
}

// ---- reader ----

namespace {

constexpr size_t kReadBytes = size_t{1} << 17;  // file bytes per read
constexpr size_t kMaxDinLineBytes = 4096;       // a longer din line is an error
// bin: records are decoded 64 payload bytes at a time, each record's 8 bytes read at its start.
constexpr size_t kBlockBytes = 64 + 8;

// `c` for a message: printable ASCII as is, anything else (NUL, control, 8-bit) as \xNN.
std::string printable(char c) {
  const auto u = static_cast<unsigned char>(c);
  if (u >= 0x20 && u < 0x7f) return std::string(1, c);
  char s[8];
  std::snprintf(s, sizeof s, "\\x%02x", u);
  return s;
}

}  // namespace

TraceReader::TraceReader(const std::filesystem::path& path) : path_(path), name_(path.string()) {
  std::error_code ec;
  if (std::filesystem::is_directory(path_, ec)) fail("is a directory, not a trace file");
  file_.reset(std::fopen(path_.c_str(), "rb"));
  if (!file_) fail("cannot open trace file");
  const uint64_t size = std::filesystem::file_size(path_, ec);
  if (ec) fail("cannot read trace file");
  // The buffer: the whole file when it is small, else one read's worth plus a din line.
  buf_.resize(static_cast<size_t>(std::min<uint64_t>(size, kReadBytes)) + kMaxDinLineBytes + 16);
  uint8_t head[kBinFixedHeaderBytes];
  const size_t got = std::fread(head, 1, sizeof head, file_.get());
  if (got >= 8 && std::memcmp(head, kBinMagic, 8) == 0) {
    if (got < kBinFixedHeaderBytes)
      fail("truncated: " + std::to_string(got) + " bytes, shorter than the " +
           std::to_string(kBinFixedHeaderBytes) + "-byte bin header");
    std::memcpy(buf_.data(), head, got);  // parse_bin_header() reads it there, then resets
    parse_bin_header(size);
  } else if (got > 0 && (head[0] == '0' || head[0] == '1' || head[0] == '2' || head[0] == ' ' ||
                         head[0] == '\t' || head[0] == '\n' || head[0] == '\r')) {
    header_.format = TraceFormat::kDin;  // count filled in as lines are read
    std::memcpy(buf_.data(), head, got);
    end_ = got;
    file_left_ = size >= got ? size - got : 0;
  } else if (got < 8 && got > 0 && std::memcmp(head, kBinMagic, got) == 0) {
    fail("truncated: " + std::to_string(got) + " bytes, shorter than the bin header");
  } else if (got == 0) {
    fail("empty file (neither a bin nor a din trace)");
  } else {
    fail("bad magic: not an RTUTRACE bin trace, and not a din trace (lines '0 <hex address>')");
  }
}

void TraceReader::fail(const std::string& what) const { throw InputError(name_ + ": " + what); }

void TraceReader::parse_bin_header(uint64_t file_bytes) {
  header_.format = TraceFormat::kBin;
  const uint8_t* p = buf_.data();
  header_.version = get_u32(p + 8);
  if (header_.version != kBinVersion)
    fail("unsupported bin trace version " + std::to_string(header_.version) + " (this build reads " +
         std::to_string(kBinVersion) + ")");
  header_.node_bytes = get_u32(p + 12);
  if (header_.node_bytes == 0 || header_.node_bytes > kMaxFetchBytes)
    fail("bad header: node size " + std::to_string(header_.node_bytes) + " bytes (need 1.." +
         std::to_string(kMaxFetchBytes) + ")");
  header_.scene_hash = get_u64(p + 16);
  header_.count = get_u64(p + 24);
  header_.checksum = get_u64(p + 32);
  header_.payload_bytes = get_u64(p + 40);
  const uint32_t name_len = get_u32(p + 48);
  if (name_len == 0 || name_len > kMaxLayoutNameBytes)
    fail("bad header: layout name length " + std::to_string(name_len));
  char name[kMaxLayoutNameBytes];
  if (std::fread(name, 1, name_len, file_.get()) != name_len)
    fail("truncated: the header's layout name is cut off");
  header_.layout.assign(name, name_len);
  for (const char c : header_.layout)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f)
      fail("bad header: layout name holds byte " + printable(c));
  const uint64_t payload_offset = kBinFixedHeaderBytes + uint64_t{name_len};
  const uint64_t have = file_bytes - payload_offset;
  if (have < header_.payload_bytes)
    fail("truncated: payload has " + std::to_string(have) + " of " +
         std::to_string(header_.payload_bytes) + " bytes");
  if (have > header_.payload_bytes)
    fail(std::to_string(have - header_.payload_bytes) + " bytes of trailing data after the payload");
  // Every record takes 1..10 bytes.
  if (header_.count > header_.payload_bytes || header_.payload_bytes > 10 * header_.count)
    fail("bad header: " + std::to_string(header_.count) + " records cannot take " +
         std::to_string(header_.payload_bytes) + " payload bytes");
  pos_ = end_ = 0;
  file_left_ = header_.payload_bytes;
}

bool TraceReader::refill() {
  if (file_left_ == 0) return false;
  if (pos_ > 0) {
    std::memmove(buf_.data(), buf_.data() + pos_, end_ - pos_);
    end_ -= pos_;
    pos_ = 0;
  }
  const size_t want = static_cast<size_t>(std::min<uint64_t>(file_left_, buf_.size() - end_));
  if (want == 0) return false;
  const size_t got = std::fread(buf_.data() + end_, 1, want, file_.get());
  if (got == 0) fail("cannot read trace file (it shrank while being read)");
  end_ += got;
  file_left_ -= got;
  return true;
}

bool TraceReader::next(std::vector<uint64_t>& addrs, std::vector<uint32_t>& sizes,
                       size_t max_records) {
  sizes.clear();
  if (done_) {
    addrs.clear();
    return false;
  }
  return header_.format == TraceFormat::kBin ? next_bin(addrs, max_records)
                                             : next_din(addrs, sizes, max_records);
}

namespace {

#if defined(__SSE2__)
// Bit i set when byte p[i] (i < 64) ends a varint (its high bit is clear).
uint64_t varint_stops64(const uint8_t* p) {
#if defined(__AVX2__)
  const auto lo = static_cast<uint32_t>(
      _mm256_movemask_epi8(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p))));
  const auto hi = static_cast<uint32_t>(
      _mm256_movemask_epi8(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p + 32))));
  return ~((uint64_t{hi} << 32) | lo);
#else
  uint64_t m = 0;
  for (int i = 0; i < 4; ++i)
    m |= uint64_t{static_cast<uint16_t>(_mm_movemask_epi8(
             _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + 16 * i))))}
         << (16 * i);
  return ~m;
#endif
}
#endif

// The zig-zag value of a varint of `len` (1..8) bytes, given the 8 little-endian bytes at its
// start: the low 7 bits of each of its bytes, concatenated.
// pext only where the target is known to have a fast one (one micro-op, 3 cycles): every
// AVX-512 machine, AMD from Zen 3 and the Intel cores from Haswell on. AMD before Zen 3 (Zen 1
// and 2, Excavator) has BMI2 with a microcoded pext (tens to hundreds of cycles). The compiler's
// target macros decide (GCC and Clang define __znver3__, __haswell__ ... for -march=<cpu> and
// -march=native); a BMI2 target without one (-march=x86-64-v3, -mbmi2) takes shifts and masks.
#if defined(__BMI2__) &&                                                                \
    (defined(__AVX512F__) || defined(__znver3__) || defined(__znver4__) ||              \
     defined(__znver5__) || defined(__haswell__) || defined(__broadwell__) ||           \
     defined(__skylake__) || defined(__alderlake__))
#define RTUSIM_FAST_PEXT 1
#endif
uint64_t varint_value(uint64_t w, unsigned len) {
#if defined(RTUSIM_FAST_PEXT)
  return _pext_u64(w, _bzhi_u64(0x7f7f7f7f7f7f7f7full, len * 8));
#else
  uint64_t x = w & (~uint64_t{0} >> (64 - 8 * len)) & 0x7f7f7f7f7f7f7f7full;
  x = (x & 0x007f007f007f007full) | ((x & 0x7f007f007f007f00ull) >> 1);
  x = (x & 0x00003fff00003fffull) | ((x & 0x3fff00003fff0000ull) >> 2);
  return (x & 0x000000000fffffffull) | ((x & 0x0fffffff00000000ull) >> 4);
#endif
}

// The signed difference (modulo 2^64) a zig-zag value stands for.
uint64_t unzigzag(uint64_t z) { return (z >> 1) ^ (0 - (z & 1)); }

uint64_t load_le64(const uint8_t* p) {
  uint64_t w;
  std::memcpy(&w, p, 8);
  if constexpr (std::endian::native == std::endian::big) w = __builtin_bswap64(w);
  return w;
}

}  // namespace

// One varint record at p (advanced past it), as the signed difference it encodes. kChecked:
// stop at `end` (else the caller guarantees 10 readable bytes).
template <bool kChecked>
uint64_t TraceReader::read_varint(const uint8_t*& p, const uint8_t* end, uint64_t record) const {
  uint64_t z = 0;
  for (int shift = 0;; shift += 7) {
    if (kChecked && p == end)
      fail("truncated: payload ends inside record " + std::to_string(record) + " of " +
           std::to_string(header_.count));
    const uint8_t b = *p++;
    if (shift == 63 && b > 1) fail("bad varint in record " + std::to_string(record));
    z |= uint64_t{b & 0x7fu} << shift;
    if (!(b & 0x80)) break;
    if (shift == 63) fail("bad varint in record " + std::to_string(record));
  }
  return unzigzag(z);
}

bool TraceReader::next_bin(std::vector<uint64_t>& addrs, size_t max_records) {
  const uint64_t want = std::min<uint64_t>(max_records, header_.count - records_);
  addrs.resize(static_cast<size_t>(want));  // from the last chunk's size: rarely writes
  uint64_t* out = addrs.data();
  uint64_t prev = prev_, h = hash_;
  size_t n = 0;
  // One record's difference: the running address, its output slot and the checksum.
  auto emit = [&](uint64_t d) {
    prev += d;
    out[n++] = prev;
    h = (h ^ prev) * kFnvPrime;
  };
  while (n < want) {
    if (end_ - pos_ < kBlockBytes) refill();
    const uint8_t* p = buf_.data() + pos_;
    const uint8_t* const end = buf_.data() + end_;
#if defined(__SSE2__)
    // 64 bytes at a time: the high bits say where each record ends, so the records are
    // decoded without a branch on their lengths (mostly 1, 2 or 3 bytes, in no pattern). A
    // record's 8 bytes are read at its start, so a block needs 64 + 8 bytes in the buffer.
    while (n < want && size_t(end - p) >= kBlockBytes) {
      uint64_t stops = varint_stops64(p);
      // Bit i of run8: bytes i .. i+7 all continue a record, so one of 9 bytes or more (or a
      // bad one) starts in the block. That block goes a record at a time through the byte
      // loop, which rejects a varint of more than 64 bits; so does one in which no record ends.
      const uint64_t more = ~stops, run2 = more & (more >> 1), run4 = run2 & (run2 >> 2);
      if ((run4 & (run4 >> 4)) != 0 || stops == 0) {
        emit(read_varint<false>(p, end, records_ + n));
        continue;
      }
      // The chunk's last block: only the records still wanted.
      if (static_cast<uint64_t>(std::popcount(stops)) > want - n) {
        uint64_t rest = stops;
        for (uint64_t k = want - n; k > 0; --k) rest &= rest - 1;
        stops ^= rest;
      }
      unsigned start = 0;  // of the next record, in the block
      do {
        const unsigned e = static_cast<unsigned>(std::countr_zero(stops));
        emit(unzigzag(varint_value(load_le64(p + start), e + 1 - start)));
        start = e + 1;
        stops &= stops - 1;
      } while (stops != 0);
      p += start;
    }
#endif
    if (end - p >= 10) {
      // Records whose 10 bytes are all in the buffer: no bounds check per byte.
      const uint8_t* const safe = end - 9;
      while (n < want && p < safe) emit(read_varint<false>(p, end, records_ + n));
    } else if (n < want) {
      // The payload's last few bytes: one record, checked byte by byte.
      emit(read_varint<true>(p, end, records_ + n));
    }
    pos_ = static_cast<size_t>(p - buf_.data());
  }
  prev_ = prev;
  hash_ = h;
  records_ += n;
  if (records_ == header_.count) {
    // The end: nothing may follow the last record, and the checksum must match.
    const uint64_t left = (end_ - pos_) + file_left_;
    if (left != 0)
      fail("payload holds " + std::to_string(left) + " bytes beyond the header's " +
           std::to_string(header_.count) + " records");
    if (hash_ != header_.checksum)
      fail("checksum mismatch: header " + hex64(header_.checksum) + ", addresses " + hex64(hash_));
    done_ = true;
  }
  return n > 0;
}

bool TraceReader::next_din(std::vector<uint64_t>& addrs, std::vector<uint32_t>& sizes,
                           size_t max_records) {
  addrs.clear();
  while (addrs.size() < max_records) {
    const char* p = reinterpret_cast<const char*>(buf_.data()) + pos_;
    const char* end = reinterpret_cast<const char*>(buf_.data()) + end_;
    const char* eol = static_cast<const char*>(std::memchr(p, '\n', size_t(end - p)));
    if (!eol) {
      if (end_ - pos_ > kMaxDinLineBytes)
        fail("line " + std::to_string(line_ + 1) + ": longer than " +
             std::to_string(kMaxDinLineBytes) + " bytes");
      if (refill()) continue;
      if (pos_ == end_) {
        done_ = true;
        break;
      }
      eol = end;  // the last line has no newline
    }
    ++line_;
    if (size_t(eol - p) > kMaxDinLineBytes)
      fail("line " + std::to_string(line_) + ": longer than " + std::to_string(kMaxDinLineBytes) +
           " bytes");
    pos_ = static_cast<size_t>(eol - reinterpret_cast<const char*>(buf_.data())) + (eol < end);
    din_line(p, eol, addrs, sizes);
  }
  records_ += addrs.size();
  header_.count = records_;
  if (!sizes.empty()) sizes.resize(addrs.size(), 0);
  return !addrs.empty();
}

// One din line [q, eol): blank, or label, hex address and an optional hex size.
void TraceReader::din_line(const char* q, const char* eol, std::vector<uint64_t>& addrs,
                           std::vector<uint32_t>& sizes) {
  auto at = [this] { return "line " + std::to_string(line_) + ": "; };
  if (q < eol && eol[-1] == '\r') --eol;
  auto skip_blanks = [&] {
    while (q < eol && (*q == ' ' || *q == '\t')) ++q;
  };
  // A hex number of 1..max_digits digits, ending at a blank or the line's end.
  auto hex = [&](const char* what, int max_digits) {
    if (q + 1 < eol && q[0] == '0' && (q[1] == 'x' || q[1] == 'X')) q += 2;
    uint64_t v = 0;
    int digits = 0;
    for (; q < eol && *q != ' ' && *q != '\t'; ++q, ++digits) {
      const char c = *q;
      int d;
      if (c >= '0' && c <= '9') d = c - '0';
      else if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
      else if (c >= 'A' && c <= 'F') d = c - 'A' + 10;
      else fail(at() + "'" + printable(c) + "' is not a hex digit");
      v = (v << 4) | static_cast<uint64_t>(d);
    }
    if (digits == 0 || digits > max_digits)
      fail(at() + "expected a hex " + what + " of 1 to " + std::to_string(max_digits) + " digits");
    return v;
  };
  skip_blanks();
  if (q == eol) return;  // blank line
  if (!(*q == '0' || *q == '1' || *q == '2') || q + 1 == eol || (q[1] != ' ' && q[1] != '\t'))
    fail(at() + "expected '<label 0-2> <hex address> [<hex size>]'");
  q += 2;
  skip_blanks();
  const uint64_t a = hex("address", 16);
  skip_blanks();
  if (q != eol) {
    const uint64_t size = hex("size", 8);
    if (size == 0 || size > kMaxFetchBytes)
      fail(at() + "access size " + std::to_string(size) + " bytes (need 1.." +
           std::to_string(kMaxFetchBytes) + ")");
    skip_blanks();
    if (q != eol) fail(at() + "unexpected '" + printable(*q) + "' after the size");
    if (a > ~uint64_t{0} - (size - 1))
      fail(at() + "an access of " + std::to_string(size) + " bytes at 0x" + hex64(a) +
           " runs past the top of the 64-bit address space");
    sizes.resize(addrs.size(), 0);
    sizes.push_back(static_cast<uint32_t>(size));
  }
  addrs.push_back(a);
}

std::vector<uint64_t> TraceReader::decode() const {
  TraceReader again(path_);
  std::vector<uint64_t> all, chunk;
  std::vector<uint32_t> sizes;
  while (again.next(chunk, sizes, size_t{1} << 16)) all.insert(all.end(), chunk.begin(), chunk.end());
  return all;
}

}  // namespace rtusim
