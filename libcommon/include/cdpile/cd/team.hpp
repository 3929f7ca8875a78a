/// A fixed team of threads for the solver's parallel stages (docs/method.md, "Threads").
///
/// The caller is thread 0; `threads - 1` workers wait between jobs. `run(job)` runs
/// job(t) on every thread t of the team and returns when all have finished; inside a job,
/// `barrier()` waits until every thread has reached it (the colours of a sweep are
/// separated so). Waiting spins briefly, then sleeps on the atomic (std::atomic::wait),
/// so an idle team costs nothing between steps and a sweep's barriers cost a few
/// microseconds. Nothing here decides how work is split: that is the schedule's
/// (schedule.hpp), so that no result depends on the number of threads.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <thread>
#include <vector>

namespace cdpile::cd {

class Team {
 public:
  /// `threads` >= 1 (1: no workers, run() calls the job in place).
  explicit Team(int threads);
  ~Team();
  Team(const Team&) = delete;
  Team& operator=(const Team&) = delete;

  int size() const { return size_; }
  /// Work over fewer positions than this runs on the calling thread alone (schedule.hpp):
  /// it takes less time than the team takes to meet. The numbers are the same either way;
  /// tests set 0 so that their small scenes go through the threads.
  std::size_t smallest_shared() const { return smallest_shared_; }
  void set_smallest_shared(std::size_t n) { smallest_shared_ = n; }
  /// At some 15 ns per local solve a sweep of 2000 contacts takes 30 microseconds, of the
  /// order of waking the team and meeting it at a barrier per colour.
  static constexpr std::size_t kSmallestShared = 2048;
  /// Runs job(t) for t = 0 .. size() - 1, t = 0 on the calling thread. A job must not
  /// throw (a worker that throws terminates the program, as any std::thread does).
  void run(const std::function<void(int)>& job);
  /// Inside run(): returns once every thread of the team has called it.
  void barrier();

 private:
  void work(int t);

  int size_;
  std::size_t smallest_shared_ = kSmallestShared;
  std::vector<std::thread> workers_;
  const std::function<void(int)>* job_ = nullptr;
  std::atomic<std::uint32_t> generation_{0};  // a new job (or the end, with stop_)
  std::atomic<int> finished_{0};              // workers done with the current job
  std::atomic<int> arrived_{0};               // threads at the current barrier
  std::atomic<std::uint32_t> phase_{0};       // barriers passed
  std::atomic<bool> stop_{false};
};

/// The threads a machine offers (std::thread::hardware_concurrency, at least 1).
int hardware_threads();

}  // namespace cdpile::cd
