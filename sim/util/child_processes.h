// Jobs in forked child processes, for work that cannot share a process (SystemC's kernel is
// global state): each job runs in a child of its own, at most `max_at_once` alive, and sends
// its result bytes back to the parent over a pipe.
//
// The child is a copy of the parent at fork time with only the calling thread: a job must not
// need another thread of the parent (a oneTBB pool, a SystemC kernel built on threads). The
// child ends with _exit (no destructors, no atexit handlers: the parent's staged outputs stay
// the parent's) after flushing its stdio; the parent's stdio is flushed before each fork so
// nothing buffered is written twice. A child dies with its parent (PR_SET_PDEATHSIG).
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace rtusim {

// Runs job(0) ... job(count - 1), each in a child process, and returns their results in job
// order. Failures are those of a loop running the jobs in order: the lowest-numbered failing
// job's error is thrown (an InputError from the child again as an InputError with its message,
// any other exception as std::runtime_error with its message, a child that died without a
// result as std::runtime_error naming `names[i]`), jobs after it are stopped (SIGTERM) or not
// started, and every child is reaped before this returns or throws.
std::vector<std::string> run_in_child_processes(size_t count, int max_at_once,
                                                const std::vector<std::string>& names,
                                                const std::function<std::string(size_t)>& job);

}  // namespace rtusim
