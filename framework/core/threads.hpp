#pragma once
// Loops of one process over independent items on several threads.
//
// Every item writes only its own outputs (a zone its stress and its share of forces, a contact
// its law state), and whatever several items add into (gridpoint forces) is added afterwards in
// item order. So a run gives the same results, to the bit, on any number of threads; threads
// only share the work. They come on top of MPI's processes (docs/parallel.md, "Threads"): each
// process runs its loops on its own threads, and the threads never call MPI.
//
// The threads are a team of our own (threads.cpp), not OpenMP's: between loops an idle thread
// waits by spinning a little while and yielding its core at every turn, then sleeping. GCC's
// OpenMP runtime spins without yielding for about a millisecond; with more threads than cores
// (two processes of two threads on two cores) the spinning threads took the cores from the
// working ones and a 2.3 s run took 107 s (docs/performance.md, "Threads").
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <limits>
#include <mutex>

namespace rockdem {

// Loops shorter than this run on the calling thread: waking the team costs microseconds.
inline constexpr std::ptrdiff_t kThreadedLoopMin = 256;

namespace detail {
// Runs job(context, t) for t = 0 .. threads - 1, t = 0 on the calling thread and the others on
// the process's team (started at first use, grown when more are asked for); returns when all
// are done. job must not throw. Calls from several threads at once take turns; a call from inside
// a job runs all its shares on that thread.
void run_on_team(int threads, void (*job)(void*, int), void* context);

// The lowest failing item's exception, kept while the team runs.
struct FirstError {
  std::mutex mutex;
  std::ptrdiff_t item = std::numeric_limits<std::ptrdiff_t>::max();
  std::exception_ptr error;
  void keep(std::ptrdiff_t i) {
    const std::lock_guard<std::mutex> lock(mutex);
    if (i < item) {
      item = i;
      error = std::current_exception();
    }
  }
  void rethrow() const {
    if (error) std::rethrow_exception(error);
  }
};

template <class Job>
void run_job(int threads, Job& job) {
  run_on_team(threads, [](void* c, int t) { (*static_cast<Job*>(c))(t); }, &job);
}
}  // namespace detail

// Calls f(i) for every i in [first, last), on up to `threads` threads, each taking one contiguous
// stretch. f may throw: the loop then finishes the other items and rethrows the exception of the
// lowest i, so the error a run stops with does not depend on the thread count.
template <class F>
void threaded_for(int threads, std::ptrdiff_t first, std::ptrdiff_t last, F&& f) {
  if (threads <= 1 || last - first < kThreadedLoopMin) {
    for (std::ptrdiff_t i = first; i < last; ++i) f(i);
    return;
  }
  detail::FirstError failed;
  const std::ptrdiff_t n = last - first;
  auto job = [&](int t) {
    const std::ptrdiff_t a = first + n * t / threads, b = first + n * (t + 1) / threads;
    for (std::ptrdiff_t i = a; i < b; ++i) {
      try {
        f(i);
      } catch (...) {
        failed.keep(i);
      }
    }
  };
  detail::run_job(threads, job);
  failed.rethrow();
}

// Calls f(c) for every chunk c in [0, chunks), each on whichever thread is free next (chunks of
// uneven cost: stretches of a detection's block pairs). Exceptions as threaded_for.
template <class F>
void threaded_chunks(int threads, std::ptrdiff_t chunks, F&& f) {
  if (threads <= 1) {
    for (std::ptrdiff_t c = 0; c < chunks; ++c) f(c);
    return;
  }
  detail::FirstError failed;
  std::atomic<std::ptrdiff_t> next{0};
  auto job = [&](int) {
    for (std::ptrdiff_t c = next++; c < chunks; c = next++) {
      try {
        f(c);
      } catch (...) {
        failed.keep(c);
      }
    }
  };
  detail::run_job(threads, job);
  failed.rethrow();
}

// The largest of 0 and f(i) for i in [first, last), on up to `threads` threads; f must not throw.
// A maximum does not depend on the order it is taken in, so neither on the thread count (a NaN
// f(i) is passed over, as std::max(best, NaN) passes it over on one thread).
template <class F>
double threaded_max(int threads, std::ptrdiff_t first, std::ptrdiff_t last, F&& f) {
  auto stretch = [&](std::ptrdiff_t a, std::ptrdiff_t b) {
    double best = 0.0;
    for (std::ptrdiff_t i = a; i < b; ++i) best = std::max(best, static_cast<double>(f(i)));
    return best;
  };
  if (threads <= 1 || last - first < kThreadedLoopMin) return stretch(first, last);
  constexpr int kMaxParts = 64;
  double part[kMaxParts] = {};
  const int parts = std::min(threads, kMaxParts);
  const std::ptrdiff_t n = last - first;
  auto job = [&](int t) {
    if (t < parts) part[t] = stretch(first + n * t / parts, first + n * (t + 1) / parts);
  };
  detail::run_job(threads, job);
  double best = 0.0;
  for (int t = 0; t < parts; ++t) best = std::max(best, part[t]);
  return best;
}

// How many cores this process may run on (its CPU affinity mask), 0 if unknown.
int usable_cores();

}  // namespace rockdem
