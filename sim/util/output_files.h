// All-or-nothing output. A run's files are written into a hidden staging directory beside the
// output directory and moved into place by commit() with one rename (or one atomic exchange
// when the output directory exists already), so a run that fails, or is stopped by SIGINT or
// SIGTERM (install_output_cleanup()), leaves either every output or none, and no staging
// directory. Write failures (full disk, unwritable directory) are InputErrors (exit 2).
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace rtusim {

// Installs SIGINT/SIGTERM/SIGHUP handlers that remove every registered staging directory and
// temporary file, then die of the signal. Commits run with these signals blocked, so a signal
// lands either before (nothing left) or after (everything in place).
void install_output_cleanup();
// In a forked child: forgets the staged outputs inherited from the parent, which are the
// parent's to commit or remove; the child's signal cleanup then removes only its own.
void forget_inherited_outputs();

class OutputFiles {
 public:
  explicit OutputFiles(std::filesystem::path dir);
  ~OutputFiles();  // removes the staging directory if commit() was not reached
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;

  // Path to write `name` (a plain file name) to, inside the staging directory.
  std::filesystem::path stage(const std::string& name);
  void write_text(const std::string& name, const std::string& text);
  // Files of an existing output directory that `earlier_output` names (an earlier run's
  // outputs of the kinds this one may write) go at commit() when this run does not write them.
  void replace_earlier(std::function<bool(const std::string&)> earlier_output) {
    earlier_output_ = std::move(earlier_output);
  }
  // Puts every staged file into the output directory at once. Other files of an existing output
  // directory stay; a directory in the way of an output file is an InputError before anything
  // moves.
  void commit();
  const std::filesystem::path& dir() const { return dir_; }
  const std::filesystem::path& staging() const { return staging_; }

 private:
  std::filesystem::path dir_, staging_;
  std::vector<std::string> names_;
  std::function<bool(const std::string&)> earlier_output_;
  int slot_ = -1;  // cleanup registration
  bool committed_ = false;
};

// For a single output file: writes to FILE.tmp-PID, renamed over FILE by commit(). A FILE that
// is a symbolic link is written through (its target replaced, the link kept); one that exists
// and is not a regular file (a device, a FIFO, a socket) is an InputError: renaming would
// replace it.
class OutputFile {
 public:
  explicit OutputFile(std::filesystem::path path);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  const std::filesystem::path& temp_path() const { return temp_; }
  const std::string& name() const { return name_; }  // the path as given, for messages
  void commit();

 private:
  std::string name_;
  std::filesystem::path path_, temp_;
  int slot_ = -1;
  bool committed_ = false;
};

}  // namespace rtusim
