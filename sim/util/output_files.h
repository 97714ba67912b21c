// All-or-nothing output: files are written under a hidden staging directory and moved into
// place only by commit(), so a run that fails leaves no partial output behind.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace rtusim {

class OutputFiles {
 public:
  explicit OutputFiles(std::filesystem::path dir);
  ~OutputFiles();  // removes the staging directory if commit() was not reached
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;

  // Path to write `name` to (inside the staging directory).
  std::filesystem::path stage(const std::string& name);
  void write_text(const std::string& name, const std::string& text);
  // Moves every staged file into the output directory.
  void commit();
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_, staging_;
  std::vector<std::string> names_;
  bool committed_ = false;
};

// For a single output file: writes to FILE.tmp, renamed over FILE by commit().
class OutputFile {
 public:
  explicit OutputFile(std::filesystem::path path);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  const std::filesystem::path& temp_path() const { return temp_; }
  void commit();

 private:
  std::filesystem::path path_, temp_;
  bool committed_ = false;
};

}  // namespace rtusim
