// A fixed team of threads with a spinning, then sleeping, barrier (team.hpp).
#include "cdpile/cd/team.hpp"

#include "cdpile/error.hpp"

#include <chrono>
#include <string>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace cdpile::cd {

namespace {

// A waiting thread spins for a few microseconds (longer than the wait between two
// colours of a sweep when every thread has its core), then yields its core for up to
// kYieldFor (a thread it waits for may be waiting for one: a machine running more threads
// than it has cores), then sleeps on the atomic (between steps on a large pile, and in a
// tool's work outside the engine, workers should not hold a core). The yielding spans the
// gaps between a step's jobs, the stages left on the calling thread (about a millisecond
// a step at 16 000 grains): a sleeping worker takes tens of microseconds to wake, and the
// caller then waits for it at the end of the next job. Yielding for 200 rounds only left
// the worker asleep 49 times a step in a quiet 16 000-grain window on 2 threads, and the
// caller waiting for it 0.45 s of the window's 8.9 (docs/performance.md, "The team's waits").
constexpr int kSpins = 200;
constexpr auto kYieldFor = std::chrono::milliseconds(2);

inline void pause() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#else
  std::this_thread::yield();
#endif
}

// Waits until `a` no longer holds `seen`: spins, yields, then sleeps on the atomic.
template <class T>
T wait_change(const std::atomic<T>& a, T seen) {
  for (int k = 0; k < kSpins; ++k) {
    const T now = a.load(std::memory_order_acquire);
    if (now != seen) return now;
    pause();
  }
  const auto until = std::chrono::steady_clock::now() + kYieldFor;
  do {
    const T now = a.load(std::memory_order_acquire);
    if (now != seen) return now;
    std::this_thread::yield();
  } while (std::chrono::steady_clock::now() < until);
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
