// Staged output files.
#include "util/output_files.h"

#include <fstream>

#include <unistd.h>

#include "util/error.h"

namespace rtusim {
namespace fs = std::filesystem;

OutputFiles::OutputFiles(fs::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_))
    throw InputError(dir_.string() + ": cannot create output directory");
  staging_ = dir_ / (".rtusim-staging-" + std::to_string(::getpid()));
  fs::remove_all(staging_, ec);
  fs::create_directory(staging_, ec);
  if (ec) throw InputError(dir_.string() + ": output directory is not writable");
}

OutputFiles::~OutputFiles() {
  std::error_code ec;
  fs::remove_all(staging_, ec);
}

fs::path OutputFiles::stage(const std::string& name) {
  names_.push_back(name);
  return staging_ / name;
}

void OutputFiles::write_text(const std::string& name, const std::string& text) {
  std::ofstream out(stage(name), std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + (staging_ / name).string());
}

void OutputFiles::commit() {
  for (const auto& n : names_) fs::rename(staging_ / n, dir_ / n);
  committed_ = true;
}

OutputFile::OutputFile(fs::path path) : path_(std::move(path)) {
  temp_ = path_;
  temp_ += ".tmp-" + std::to_string(::getpid());
  const fs::path parent = path_.has_parent_path() ? path_.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    throw InputError(path_.string() + ": directory " + parent.string() + " does not exist");
}

OutputFile::~OutputFile() {
  std::error_code ec;
  if (!committed_) fs::remove(temp_, ec);
}

void OutputFile::commit() {
  fs::rename(temp_, path_);
  committed_ = true;
}

}  // namespace rtusim
