#pragma once
// A request to stop a run early (SIGINT, SIGTERM): the app's signal handler records the signal,
// the stepping loop looks at it between chunks of steps, finishes the step, writes what it has and
// throws Interrupted, which main() turns into exit code 128 + signal (130, 143).
#include <atomic>
#include <stdexcept>
#include <string>

namespace rockdem {

// The signal that asked the run to stop, 0 when none. Lock-free, so a signal handler may set it.
inline std::atomic<int>& interrupt_signal() {
  static std::atomic<int> s{0};
  static_assert(std::atomic<int>::is_always_lock_free);
  return s;
}

class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, const std::string& what) : std::runtime_error(what), signal_(signal) {}
  int signal() const { return signal_; }
  int exit_code() const { return 128 + signal_; }

 private:
  int signal_;
};

}  // namespace rockdem
