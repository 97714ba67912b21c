// Forked jobs with their results over pipes (see child_processes.h).
#include "util/child_processes.h"

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <optional>
#include <stdexcept>

#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "util/error.h"
#include "util/output_files.h"

namespace rtusim {
namespace {

// The first byte a child sends: how its job ended. The rest is the result or the message.
enum class Outcome : char { kOk = 0, kInternalError = 1, kInputError = 2 };

// Writes all of `bytes` to `fd`; false when the pipe is gone.
bool write_all(int fd, const char* bytes, size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, bytes, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    bytes += n;
    size -= size_t(n);
  }
  return true;
}

// The child's side: runs the job, sends outcome and bytes, and never returns.
[[noreturn]] void run_child(int fd, size_t index, const std::function<std::string(size_t)>& job) {
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  forget_inherited_outputs();
  Outcome outcome = Outcome::kOk;
  std::string bytes;
  try {
    bytes = job(index);
  } catch (const InputError& e) {
    outcome = Outcome::kInputError;
    bytes = e.what();
  } catch (const std::exception& e) {
    outcome = Outcome::kInternalError;
    bytes = e.what();
  } catch (...) {
    outcome = Outcome::kInternalError;
    bytes = "unknown exception";
  }
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  const char head = static_cast<char>(outcome);
  const bool sent = write_all(fd, &head, 1) && write_all(fd, bytes.data(), bytes.size());
  ::_exit(sent ? 0 : 1);
}

// A running child and what it has sent so far.
struct Child {
  size_t index = 0;
  pid_t pid = -1;
  int fd = -1;
  std::string bytes;
};

// How a job failed, to be thrown once every child is reaped.
struct Failure {
  size_t index = 0;
  bool input_error = false;
  std::string message;
};

// The failure of a child that ended (status from waitpid), if it failed.
std::optional<Failure> failure_of(const Child& c, int status, const std::string& name) {
  const bool exited_ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (exited_ok && !c.bytes.empty()) {
    const auto outcome = static_cast<Outcome>(c.bytes[0]);
    if (outcome == Outcome::kOk) return std::nullopt;
    return Failure{c.index, outcome == Outcome::kInputError, c.bytes.substr(1)};
  }
  std::string how = WIFSIGNALED(status)
                        ? "died of signal " + std::to_string(WTERMSIG(status)) + " (" +
                              strsignal(WTERMSIG(status)) + ")"
                        : "exited with status " + std::to_string(WEXITSTATUS(status)) +
                              " without a result";
  return Failure{c.index, false, "the process of " + name + " " + how};
}

}  // namespace

std::vector<std::string> run_in_child_processes(size_t count, int max_at_once,
                                                const std::vector<std::string>& names,
                                                const std::function<std::string(size_t)>& job) {
  std::vector<std::string> results(count);
  std::vector<Child> alive;
  std::optional<Failure> failed;  // the lowest-numbered failure so far
  size_t next = 0;
  const size_t limit = size_t(std::max(1, max_at_once));
  auto start = [&](size_t index) {
    int fds[2];
    if (::pipe(fds) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0) {
      const int err = errno;
      ::close(fds[0]);
      ::close(fds[1]);
      throw std::runtime_error(std::string("fork: ") + std::strerror(err));
    }
    if (pid == 0) {
      ::close(fds[0]);
      for (const Child& c : alive) ::close(c.fd);
      run_child(fds[1], index, job);
    }
    ::close(fds[1]);
    alive.push_back(Child{index, pid, fds[0], {}});
  };
  // Stops the children after a failed job: a loop in order would not have run them.
  auto stop_after = [&](size_t index) {
    for (const Child& c : alive)
      if (c.index > index) ::kill(c.pid, SIGTERM);
  };
  // Reaps child `i` of `alive` (its pipe at EOF) and records its result or failure.
  auto reap = [&](size_t i) {
    Child c = std::move(alive[i]);
    alive.erase(alive.begin() + std::ptrdiff_t(i));
    ::close(c.fd);
    int status = 0;
    while (::waitpid(c.pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (std::optional<Failure> f = failure_of(c, status, names.at(c.index))) {
      if (!failed || f->index < failed->index) {
        failed = std::move(f);
        stop_after(failed->index);
      }
    } else {
      results[c.index] = c.bytes.substr(1);
    }
  };

  try {
    for (;;) {
      while (alive.size() < limit && next < count && !failed) start(next++);
      if (alive.empty()) break;
      std::vector<pollfd> polled(alive.size());
      for (size_t i = 0; i < alive.size(); ++i) polled[i] = pollfd{alive[i].fd, POLLIN, 0};
      if (::poll(polled.data(), polled.size(), -1) < 0) {
        if (errno == EINTR) continue;
        throw std::runtime_error(std::string("poll: ") + std::strerror(errno));
      }
      // Back to front, so that reaping one leaves the indices of the others in place.
      for (size_t i = polled.size(); i-- > 0;) {
        if (polled[i].revents == 0) continue;
        char buffer[1 << 16];
        const ssize_t n = ::read(alive[i].fd, buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n > 0) alive[i].bytes.append(buffer, size_t(n));
        else reap(i);
      }
    }
  } catch (...) {
    // The parent itself failed (pipe, fork, poll): no child outlives the call.
    for (const Child& c : alive) {
      ::kill(c.pid, SIGTERM);
      ::close(c.fd);
      int status = 0;
      while (::waitpid(c.pid, &status, 0) < 0 && errno == EINTR) {
      }
    }
    throw;
  }
  if (failed) {
    if (failed->input_error) throw InputError(failed->message);
    throw std::runtime_error(failed->message);
  }
  return results;
}

}  // namespace rtusim
