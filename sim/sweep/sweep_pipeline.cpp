#include "sweep/sweep_pipeline.h"

#include <algorithm>

namespace rtusim {

SweepPipeline::SweepPipeline(std::vector<CacheSweep*> sweeps, unsigned threads, size_t max_chunks)
    : max_chunks_(std::max<size_t>(1, max_chunks)) {
  for (size_t s = 0; s < sweeps.size(); ++s)
    for (size_t t = 0; t < sweeps[s]->tasks(); ++t) tasks_.push_back(Task{sweeps[s], t, s});
  // The pushing thread is one of the `threads`: it feeds tasks whenever it waits for room.
  const size_t n = std::min<size_t>(std::max(1u, threads) - 1, tasks_.size());
  for (size_t w = 0; w < n; ++w) workers_.emplace_back([this] { work(); });
}

SweepPipeline::~SweepPipeline() {
  {
    std::lock_guard lock(mutex_);
    closing_ = true;
  }
  changed_.notify_all();
  for (std::thread& w : workers_)
    if (w.joinable()) w.join();
}

void SweepPipeline::push(Lists& lists) {
  std::unique_lock lock(mutex_);
  // No room: this thread feeds tasks itself until there is, the oldest chunk's first.
  while (chunks_.size() >= max_chunks_ && !error_) {
    if (Task* t = pick(nullptr)) {
      pusher_last_ = t;
      run(*t, lock);
    } else {
      changed_.wait(lock);
    }
  }
  if (error_) std::rethrow_exception(error_);
  chunks_.push_back(std::move(lists));
  ++pushed_;
  if (tasks_.empty()) release();  // nothing to feed: no worker would release it
  if (spare_.empty()) {
    lists.assign(chunks_.back().size(), {});
  } else {
    lists = std::move(spare_.back());
    spare_.pop_back();
  }
  lock.unlock();
  changed_.notify_all();
}

void SweepPipeline::finish() {
  std::unique_lock lock(mutex_);
  closing_ = true;
  changed_.notify_all();
  // This thread feeds what is left beside the workers.
  while (!error_) {
    if (Task* t = pick(pusher_last_)) {
      pusher_last_ = t;
      run(*t, lock);
    } else if (all_fed()) {
      break;
    } else {
      changed_.wait(lock);
    }
  }
  lock.unlock();
  for (std::thread& w : workers_) w.join();
  workers_.clear();
  if (error_) std::rethrow_exception(error_);
}

bool SweepPipeline::all_fed() const {
  return std::all_of(tasks_.begin(), tasks_.end(),
                     [&](const Task& x) { return !x.busy && x.next == pushed_; });
}

SweepPipeline::Task* SweepPipeline::pick(Task* last) {
  // The task this worker fed last, while it has chunks to go: its stacks are still in this
  // core's caches.
  if (last && !last->busy && last->next < pushed_) return last;
  Task* best = nullptr;
  for (Task& t : tasks_)
    if (!t.busy && t.next < pushed_ && (!best || t.next < best->next)) best = &t;
  return best;
}

void SweepPipeline::work() {
  std::unique_lock lock(mutex_);
  Task* last = nullptr;
  for (;;) {
    Task* t = nullptr;
    changed_.wait(lock, [&] {
      t = error_ ? nullptr : pick(last);
      return t || error_ || (closing_ && all_fed());
    });
    if (!t) return;
    last = t;
    run(*t, lock);
  }
}

void SweepPipeline::run(Task& t, std::unique_lock<std::mutex>& lock) {
  t.busy = true;
  const SweepChunk& chunk = chunks_[t.next - first_][t.list];
  lock.unlock();
  try {
    t.sweep->feed_task(t.index, chunk);
  } catch (...) {
    lock.lock();
    if (!error_) error_ = std::current_exception();
    t.busy = false;
    changed_.notify_all();
    return;
  }
  lock.lock();
  t.busy = false;
  ++t.next;
  release();
  changed_.notify_all();
}

void SweepPipeline::release() {
  size_t done = pushed_;
  for (const Task& t : tasks_) done = std::min(done, t.next);
  for (; first_ < done; ++first_) {
    Lists lists = std::move(chunks_.front());
    chunks_.pop_front();
    for (auto& l : lists) l.clear();
    spare_.push_back(std::move(lists));
  }
}

}  // namespace rtusim
