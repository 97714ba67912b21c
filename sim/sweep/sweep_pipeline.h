// Feeds a stream of fetch chunks to the tasks of one or more CacheSweeps on worker threads, with
// no barrier between chunks: each task (a line-size group or a side-by-side cache) takes the
// chunks in order, one at a time, while other tasks work on earlier or later chunks, so the
// workers stay busy whatever the tasks cost; a worker keeps to the task it fed last while that
// one has chunks waiting (its stacks stay in the core's caches). A chunk is released once every
// task has fed it; at most `max_chunks` are held: push() feeds tasks itself until there is room,
// so the pushing thread is one of the `threads` (threads - 1 workers). The counts are those of
// CacheSweep::feed() over the same chunks, for any thread count.
#pragma once
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "sweep/cache_sweep.h"

namespace rtusim {

class SweepPipeline {
 public:
  using Lists = std::vector<SweepChunk>;  // a chunk: one fetch list per sweep

  // Sweep i takes list i of every chunk.
  SweepPipeline(std::vector<CacheSweep*> sweeps, unsigned threads, size_t max_chunks);
  ~SweepPipeline();
  SweepPipeline(const SweepPipeline&) = delete;
  SweepPipeline& operator=(const SweepPipeline&) = delete;

  // Queues `lists` (one per sweep, filled by its CacheSweep::record()) as the next chunk; gives
  // back emptied lists to fill next.
  void push(Lists& lists);
  // Feeds, beside the workers, until every task has fed every chunk, and stops the workers;
  // rethrows a task's error.
  void finish();

 private:
  struct Task {
    CacheSweep* sweep;
    size_t index;       // CacheSweep task index
    size_t list;        // which list of a chunk
    size_t next = 0;    // sequence number of the next chunk to feed
    bool busy = false;
  };
  // The idle task to feed next, `last` (the worker's previous one) while it has a chunk
  // waiting, else the one with the oldest chunk waiting; under the lock.
  Task* pick(Task* last);
  void work();
  // Feeds `t` its next chunk: called, and returns, under `lock`, which it drops meanwhile.
  void run(Task& t, std::unique_lock<std::mutex>& lock);
  bool all_fed() const;  // every task has fed every chunk pushed; under the lock
  void release();  // drops the chunks every task has fed; under the lock

  std::vector<Task> tasks_;
  Task* pusher_last_ = nullptr;  // the task the pushing thread fed last
  std::deque<Lists> chunks_;  // sequence numbers first_ ..
  std::vector<Lists> spare_;  // released chunks, for push() to hand back
  size_t first_ = 0, pushed_ = 0, max_chunks_;
  bool closing_ = false;
  std::exception_ptr error_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::thread> workers_;
};

}  // namespace rtusim
