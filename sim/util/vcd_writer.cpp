// VCD output.
#include "util/vcd_writer.h"

#include <stdexcept>

namespace rtusim {

VcdWriter::VcdWriter(const std::string& path, const std::string& scope)
    : file_(path), out_(file_.temp_path(), std::ios::binary), scope_(scope) {
  if (!out_) throw std::runtime_error("cannot write " + file_.temp_path().string());
}

uint32_t VcdWriter::add(const std::string& name, uint32_t width_bits) {
  // Identifier codes: printable characters '!'..'~', base 94.
  std::string code;
  for (uint32_t n = static_cast<uint32_t>(vars_.size());; n /= 94) {
    code += static_cast<char>('!' + n % 94);
    if (n < 94) break;
  }
  vars_.push_back({name, code, width_bits, 0, false});
  return static_cast<uint32_t>(vars_.size() - 1);
}

void VcdWriter::write_header() {
  out_ << "$date rtusim $end\n$version rtusim VcdWriter $end\n$timescale 1 ps $end\n"
       << "$scope module " << scope_ << " $end\n";
  for (const Var& v : vars_)
    out_ << "$var wire " << v.width << ' ' << v.code << ' ' << v.name << " $end\n";
  out_ << "$upscope $end\n$enddefinitions $end\n";
  header_written_ = true;
}

void VcdWriter::sample(uint64_t time_ps, uint32_t var, uint64_t value) {
  if (!header_written_) write_header();
  Var& v = vars_[var];
  if (v.written && v.value == value) return;
  if (time_ps < time_ps_) time_ps = time_ps_;
  if (!time_written_ || time_ps != time_ps_) {
    out_ << '#' << time_ps << '\n';
    time_ps_ = time_ps;
    time_written_ = true;
  }
  out_ << 'b';
  for (int bit = static_cast<int>(v.width) - 1; bit >= 0; --bit) out_ << ((value >> bit) & 1u);
  out_ << ' ' << v.code << '\n';
  v.value = value;
  v.written = true;
}

void VcdWriter::commit() {
  if (!header_written_) write_header();
  out_.close();
  if (!out_) throw std::runtime_error("cannot write " + file_.temp_path().string());
  file_.commit();
}

}  // namespace rtusim
