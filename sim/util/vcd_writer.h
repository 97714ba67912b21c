// A minimal VCD (IEEE 1364 value change dump) writer for models that keep their own time, such
// as the traversal unit running ahead of the SystemC kernel: variables are declared first, then
// sampled with non-decreasing times; only changes are written. The file is written under a
// temporary name and appears under its own name only on commit().
#pragma once
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "util/output_files.h"

namespace rtusim {

class VcdWriter {
 public:
  // Throws InputError when the file's directory does not exist.
  VcdWriter(const std::string& path, const std::string& scope);

  // Declares a variable of `width_bits` (before the first sample); returns its handle.
  uint32_t add(const std::string& name, uint32_t width_bits);
  // Records `value` for `var` at `time_ps` (earlier times are taken as the last time written).
  void sample(uint64_t time_ps, uint32_t var, uint64_t value);
  // Flushes and moves the file into place.
  void commit();

 private:
  void write_header();

  struct Var {
    std::string name, code;
    uint32_t width;
    uint64_t value;
    bool written;
  };
  OutputFile file_;
  std::ofstream out_;
  std::string scope_;
  std::vector<Var> vars_;
  bool header_written_ = false;
  uint64_t time_ps_ = 0;
  bool time_written_ = false;
};

}  // namespace rtusim
