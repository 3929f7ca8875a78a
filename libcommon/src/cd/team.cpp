// A fixed team of threads with a spinning, then sleeping, barrier (team.hpp).
#include "cdpile/cd/team.hpp"

#include "cdpile/error.hpp"

#include <string>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace cdpile::cd {

namespace {

// A waiting thread spins for a few microseconds (longer than the wait between two
// colours of a sweep when every thread has its core), then yields its core for a while
// (a thread it waits for may be waiting for one: a machine running more threads than it
// has cores), then sleeps on the atomic (the stages between two solves, where workers
// should not hold a core).
constexpr int kSpins = 200;
constexpr int kYields = 200;

inline void pause() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#else
  std::this_thread::yield();
#endif
}

// Waits until `a` no longer holds `seen`: spins, then sleeps on the atomic.
template <class T>
T wait_change(const std::atomic<T>& a, T seen) {
  for (int k = 0; k < kSpins + kYields; ++k) {
    const T now = a.load(std::memory_order_acquire);
    if (now != seen) return now;
    if (k < kSpins)
      pause();
    else
      std::this_thread::yield();
  }
  a.wait(seen, std::memory_order_acquire);
  return a.load(std::memory_order_acquire);
}

}  // namespace

int hardware_threads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n > 0 ? static_cast<int>(n) : 1;
}

Team::Team(int threads) : size_(threads) {
  if (threads < 1) throw UsageError("threads must be >= 1, got " + std::to_string(threads));
  workers_.reserve(static_cast<std::size_t>(threads - 1));
  for (int t = 1; t < threads; ++t) workers_.emplace_back([this, t] { work(t); });
}

Team::~Team() {
  stop_.store(true, std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  for (std::thread& w : workers_) w.join();
}

void Team::run(const std::function<void(int)>& job) {
  if (size_ == 1) {
    job(0);
    return;
  }
  job_ = &job;
  finished_.store(0, std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);  // publishes job_ to the workers
  generation_.notify_all();
  job(0);
  const int workers = size_ - 1;
  int done = finished_.load(std::memory_order_acquire);
  while (done != workers) done = wait_change(finished_, done);
  job_ = nullptr;
}

void Team::barrier() {
  if (size_ == 1) return;
  const std::uint32_t phase = phase_.load(std::memory_order_acquire);
  if (arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == size_) {
    arrived_.store(0, std::memory_order_relaxed);
    phase_.fetch_add(1, std::memory_order_release);
    phase_.notify_all();
    return;
  }
  wait_change(phase_, phase);
}

void Team::work(int t) {
  std::uint32_t seen = 0;
  for (;;) {
    seen = wait_change(generation_, seen);
    if (stop_.load(std::memory_order_relaxed)) return;
    (*job_)(t);
    finished_.fetch_add(1, std::memory_order_acq_rel);
    finished_.notify_one();
  }
}

}  // namespace cdpile::cd
