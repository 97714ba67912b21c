// Staged output files, the one-rename commit and the signal-time cleanup.
#include "util/output_files.h"

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "util/error.h"

namespace rtusim {
namespace fs = std::filesystem;
namespace {

// ---- cleanup registry, read by the signal handler (async-signal-safe calls only) ----

constexpr int kSlots = 8;
constexpr size_t kPathBytes = 4096;
struct CleanupSlot {
  volatile sig_atomic_t kind = 0;  // 0 free, 1 file, 2 flat directory
  char path[kPathBytes] = {};
};
CleanupSlot g_slots[kSlots];

int register_cleanup(const fs::path& p, int kind) {
  const std::string s = p.string();
  if (s.size() >= kPathBytes) throw InputError(s + ": path too long");
  for (int i = 0; i < kSlots; ++i)
    if (g_slots[i].kind == 0) {
      std::memcpy(g_slots[i].path, s.c_str(), s.size() + 1);
      g_slots[i].kind = kind;
      return i;
    }
  throw std::logic_error("output cleanup: more than 8 staged outputs at once");
}

void unregister_cleanup(int& slot) {
  if (slot >= 0) g_slots[slot].kind = 0;
  slot = -1;
}

// Removes a flat directory (files only) with raw system calls.
void remove_flat_dir(const char* path) {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY);
  if (fd >= 0) {
    alignas(8) char buf[4096];
    for (;;) {
      const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
      if (n <= 0) break;
      for (long off = 0; off < n;) {
        struct Dirent64 {
          uint64_t ino;
          int64_t off;
          unsigned short reclen;
          unsigned char type;
          char name[1];
        };
        const auto* d = reinterpret_cast<const Dirent64*>(buf + off);
        const char* name = buf + off + offsetof(Dirent64, name);
        if (!(name[0] == '.' && (name[1] == 0 || (name[1] == '.' && name[2] == 0))))
          ::unlinkat(fd, name, 0);
        off += d->reclen;
      }
    }
    ::close(fd);
  }
  ::rmdir(path);
}

void on_signal(int sig) {
  for (CleanupSlot& s : g_slots) {
    if (s.kind == 1) ::unlink(s.path);
    if (s.kind == 2) remove_flat_dir(s.path);
    s.kind = 0;
  }
  std::signal(sig, SIG_DFL);
  ::raise(sig);
}

constexpr int kCleanupSignals[] = {SIGINT, SIGTERM, SIGHUP};
constexpr unsigned kRenameExchange = 1u << 1;  // RENAME_EXCHANGE of renameat2(2)

// Blocks the cleanup signals for its lifetime (a commit runs to its end, then they arrive).
class SignalBlock {
 public:
  SignalBlock() {
    sigset_t set;
    sigemptyset(&set);
    for (int s : kCleanupSignals) sigaddset(&set, s);
    ::sigprocmask(SIG_BLOCK, &set, &old_);
  }
  ~SignalBlock() { ::sigprocmask(SIG_SETMASK, &old_, nullptr); }

 private:
  sigset_t old_;
};

std::string errno_text() { return std::strerror(errno); }

}  // namespace

void install_output_cleanup() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  for (int s : kCleanupSignals) sigaddset(&sa.sa_mask, s);
  for (int s : kCleanupSignals) ::sigaction(s, &sa, nullptr);
}

void forget_inherited_outputs() {
  for (CleanupSlot& s : g_slots) s.kind = 0;
}

// ---- OutputFiles ----

OutputFiles::OutputFiles(fs::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  dir_ = fs::absolute(dir_, ec).lexically_normal();  // "out/", "." and ".." get a name
  if (dir_.filename().empty()) dir_ = dir_.parent_path();
  if (fs::exists(dir_, ec) && !fs::is_directory(dir_, ec))
    throw InputError(dir_.string() + ": exists and is not a directory");
  const fs::path parent = dir_.has_parent_path() ? dir_.parent_path() : fs::path(".");
  fs::create_directories(parent, ec);
  if (ec || !fs::is_directory(parent))
    throw InputError(dir_.string() + ": cannot create output directory " + parent.string());
  staging_ = parent / (".rtusim-staging-" + dir_.filename().string() + "-" +
                       std::to_string(::getpid()));
  fs::remove_all(staging_, ec);
  slot_ = register_cleanup(staging_, 2);
  if (::mkdir(staging_.c_str(), 0777) != 0)
    throw InputError(dir_.string() + ": cannot make a directory in " + parent.string() + " (" +
                     errno_text() + ")");
}

OutputFiles::~OutputFiles() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);
  unregister_cleanup(slot_);
}

fs::path OutputFiles::stage(const std::string& name) {
  if (name.empty() || name.find('/') != std::string::npos)
    throw std::logic_error("output name '" + name + "' is not a plain file name");
  if (std::find(names_.begin(), names_.end(), name) == names_.end()) names_.push_back(name);
  return staging_ / name;
}

void OutputFiles::write_text(const std::string& name, const std::string& text) {
  const fs::path p = stage(name);
  std::ofstream out(p, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw InputError((dir_ / name).string() + ": cannot write (" + errno_text() + ")");
}

void OutputFiles::commit() {
  std::error_code ec;
  const bool existed = fs::exists(dir_, ec);
  std::vector<std::string> subdirs;  // directories of the old output directory to move back
  // A directory holding the working directory is not swapped away under the process (or a
  // shell); its files are renamed into it one by one instead, still with the signals blocked.
  const fs::path cwd = fs::current_path(ec);
  const bool holds_cwd = existed && !ec &&
                         std::mismatch(dir_.begin(), dir_.end(), cwd.begin(), cwd.end()).first ==
                             dir_.end();
  // An entry of the old directory: a directory of its own (not a link to one), and whether it
  // is an earlier run's output this run drops (replace_earlier(): not written now).
  std::error_code entry_ec;  // a dangling link's status is not an error of the directory
  const auto own_dir = [&](const fs::directory_entry& e) {
    return e.is_directory(entry_ec) && !e.is_symlink(entry_ec);
  };
  const auto dropped = [&](const fs::directory_entry& e, const std::string& n) {
    return earlier_output_ && earlier_output_(n) && !own_dir(e) &&
           std::find(names_.begin(), names_.end(), n) == names_.end();
  };
  if (existed) {
    // An output directory from before: nothing may stand in the way of an output file, and its
    // other files join the staged ones (hard links) so the exchange keeps them.
    for (const auto& n : names_)
      if (fs::is_directory(dir_ / n, entry_ec))
        throw InputError((dir_ / n).string() + ": is a directory, cannot write an output file there");
    for (const fs::directory_entry& e : fs::directory_iterator(dir_, ec)) {
      if (holds_cwd) break;
      const std::string n = e.path().filename().string();
      if (std::find(names_.begin(), names_.end(), n) != names_.end() || dropped(e, n)) continue;
      if (own_dir(e)) {
        subdirs.push_back(n);
      } else if (::link(e.path().c_str(), (staging_ / n).c_str()) != 0) {
        throw InputError(dir_.string() + ": cannot keep its file " + n + " (" + errno_text() + ")");
      }
    }
    if (ec) throw InputError(dir_.string() + ": cannot read the output directory (" + ec.message() + ")");
  }
  {
    const SignalBlock block;
    if (holds_cwd) {
      for (const auto& n : names_)
        if (::rename((staging_ / n).c_str(), (dir_ / n).c_str()) != 0)
          throw InputError((dir_ / n).string() + ": cannot write (" + errno_text() + ")");
      fs::remove_all(staging_, ec);
      if (earlier_output_)
        for (const fs::directory_entry& e : fs::directory_iterator(dir_, ec))
          if (dropped(e, e.path().filename().string())) fs::remove(e.path(), ec);
    } else if (!existed) {
      if (::rename(staging_.c_str(), dir_.c_str()) != 0)
        throw InputError(dir_.string() + ": cannot create the output directory (" + errno_text() + ")");
    } else {
      if (::syscall(SYS_renameat2, AT_FDCWD, staging_.c_str(), AT_FDCWD, dir_.c_str(),
                    kRenameExchange) != 0)
        throw InputError(dir_.string() + ": cannot replace the output directory (" + errno_text() + ")");
      // staging_ now holds the old directory: move its subdirectories back, drop the rest.
      for (const auto& n : subdirs) fs::rename(staging_ / n, dir_ / n, ec);
      fs::remove_all(staging_, ec);
    }
    committed_ = true;
    unregister_cleanup(slot_);
  }
}

// ---- OutputFile ----

OutputFile::OutputFile(fs::path path) : name_(path.string()), path_(std::move(path)) {
  std::error_code ec;
  if (fs::is_directory(path_, ec))
    throw InputError(name_ + ": is a directory (need a file name)");
  // A symbolic link is written through (its target replaced, the link kept), a dangling one
  // too (its target made).
  for (int hops = 0; fs::is_symlink(fs::symlink_status(path_, ec)); ++hops) {
    if (hops == 40) throw InputError(name_ + ": too many levels of symbolic links");
    const fs::path target = fs::read_symlink(path_, ec);
    if (ec) throw InputError(name_ + ": cannot read the link (" + ec.message() + ")");
    path_ = (target.is_absolute() ? target : path_.parent_path() / target).lexically_normal();
  }
  if (path_.string() != name_ && fs::is_directory(path_, ec))
    throw InputError(name_ + ": links to a directory (need a file name)");
  if (fs::exists(fs::status(path_, ec)) && !fs::is_regular_file(path_, ec))
    throw InputError(name_ + ": exists and is not a regular file (a device, FIFO or socket); "
                     "rtusim writes a file beside it and renames it into place");
  temp_ = path_;
  temp_ += ".tmp-" + std::to_string(::getpid());
  const fs::path parent = path_.has_parent_path() ? path_.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec))
    throw InputError(name_ + ": directory " + parent.string() + " does not exist");
  if (::access(parent.c_str(), W_OK) != 0)
    throw InputError(name_ + ": directory " + parent.string() + " is not writable");
  slot_ = register_cleanup(temp_, 1);
}

OutputFile::~OutputFile() {
  std::error_code ec;
  if (!committed_) fs::remove(temp_, ec);
  unregister_cleanup(slot_);
}

void OutputFile::commit() {
  const SignalBlock block;
  if (::rename(temp_.c_str(), path_.c_str()) != 0)
    throw InputError(name_ + ": cannot write (" + errno_text() + ")");
  committed_ = true;
  unregister_cleanup(slot_);
}

}  // namespace rtusim
