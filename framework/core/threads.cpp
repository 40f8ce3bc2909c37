#include "framework/core/threads.hpp"

#include <sched.h>

#include <chrono>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace rockdem {
namespace detail {
namespace {

// How long an idle thread looks for new work before it sleeps. The engine's loops come every few
// tens to hundreds of microseconds within a step: a thread asleep takes a system call and a
// scheduler wake-up to start again, one awake starts at once.
constexpr auto kSpin = std::chrono::microseconds(2000);

// Whether this thread is running a share of a loop (a worker always is).
thread_local bool inside_job = false;

// Returns once `word` is no longer `old`: looks again and again for kSpin, giving up its core at
// every turn (sched_yield: a thread with work, of this process or of another on the same core,
// runs instead), then sleeps on the word until it is notified.
void await_change(const std::atomic<std::uint32_t>& word, std::uint32_t old) {
  const auto start = std::chrono::steady_clock::now();
  for (unsigned i = 1;; ++i) {
    if (word.load(std::memory_order_acquire) != old) return;
    if (i % 64 == 0 && std::chrono::steady_clock::now() - start > kSpin) break;
    sched_yield();
  }
  while (word.load(std::memory_order_acquire) == old) word.wait(old, std::memory_order_acquire);
}

// The process's threads beyond the calling one. A run publishes its job, moves `generation_` on
// and does its own share; every worker does its share (or nothing, beyond the threads asked for)
// and counts `pending_` down, so that no worker is still in one run when the next starts.
class Team {
 public:
  ~Team() {
    stop_ = true;
    generation_.fetch_add(1, std::memory_order_acq_rel);
    generation_.notify_all();
    for (auto& w : workers_) w.join();
  }

  void run(int threads, void (*job)(void*, int), void* context) {
    while (static_cast<int>(workers_.size()) < threads - 1) {
      const int index = static_cast<int>(workers_.size()) + 1;
      workers_.emplace_back([this, index, seen = generation_.load(std::memory_order_acquire)] { work(index, seen); });
    }
    job_ = job;
    context_ = context;
    active_ = threads;
    pending_.store(static_cast<std::uint32_t>(workers_.size()), std::memory_order_release);
    generation_.fetch_add(1, std::memory_order_acq_rel);
    generation_.notify_all();
    // The workers are waited for even if this thread's share throws (the job must not, but a run
    // that returned early would leave them working on a finished caller's stack).
    std::exception_ptr error;
    try {
      job(context, 0);
    } catch (...) {
      error = std::current_exception();
    }
    for (std::uint32_t p = pending_.load(std::memory_order_acquire); p != 0; p = pending_.load(std::memory_order_acquire))
      await_change(pending_, p);
    if (error) std::rethrow_exception(error);
  }

 private:
  void work(int index, std::uint32_t seen) {
    inside_job = true;  // a loop a job starts runs on this thread (run_on_team)
    for (;;) {
      await_change(generation_, seen);
      seen = generation_.load(std::memory_order_acquire);
      if (stop_) return;
      if (index < active_) job_(context_, index);
      if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) pending_.notify_all();
    }
  }

  std::vector<std::thread> workers_;
  std::atomic<std::uint32_t> generation_{0}, pending_{0};
  // Written by the calling thread before generation_ moves on, read by the workers after.
  void (*job_)(void*, int) = nullptr;
  void* context_ = nullptr;
  int active_ = 0;
  bool stop_ = false;
};

}  // namespace

void run_on_team(int threads, void (*job)(void*, int), void* context) {
  // A loop started inside a loop's job (not done today) runs on its thread, share by share: the
  // team is busy with the outer loop and waiting for it would never end.
  if (inside_job) {
    for (int t = 0; t < threads; ++t) job(context, t);
    return;
  }
  static Team team;
  static std::mutex one_at_a_time;  // two engines stepping on two threads take turns with the team
  const std::lock_guard<std::mutex> lock(one_at_a_time);
  inside_job = true;
  struct Leave {
    ~Leave() { inside_job = false; }
  } leave;
  team.run(threads, job, context);
}

}  // namespace detail

int usable_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 0;
  return CPU_COUNT(&set);
}

}  // namespace rockdem
