// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/core/parallel.h"

#if defined(RAMIFORM_PARALLEL_STD_THREADS)
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>
#else
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <map>
#include <mutex>
#endif

namespace ramiform::parallel {
namespace {

// True while this thread runs the body of a loop that its Context made serial (threads == 1):
// loops nested in it that were given no Context stay serial too, so `threads = 1` means one
// thread all the way down. (Nested loops in a multi-threaded loop run in its task arena, so
// they keep its thread count without this.)
thread_local bool in_serial_loop = false;

// Sets in_serial_loop for a scope and restores the outer value, also when the body throws.
class SerialScope {
 public:
  SerialScope() : outer_(in_serial_loop) { in_serial_loop = true; }
  ~SerialScope() { in_serial_loop = outer_; }
  SerialScope(const SerialScope&) = delete;
  SerialScope& operator=(const SerialScope&) = delete;

 private:
  bool outer_;
};

#if !defined(RAMIFORM_PARALLEL_STD_THREADS)
// One task arena per thread count, made on first use and kept: making an arena for every loop
// cost up to milliseconds a call (a line tracer's thousands of small batched evaluations took
// seconds), and loops of one Context now share its arena's threads. Never destroyed (the
// workers may outlive static destructors).
tbb::task_arena& arena_for(int threads) {
  static std::mutex mutex;
  static auto* arenas = new std::map<int, tbb::task_arena*>();
  const std::lock_guard<std::mutex> lock(mutex);
  tbb::task_arena*& arena = (*arenas)[threads];
  if (arena == nullptr) {
    arena = new tbb::task_arena(threads);
    arena->initialize();
  }
  return *arena;
}
#endif

}  // namespace

void for_chunks(std::size_t n, std::size_t grain,
                const std::function<void(std::size_t, std::size_t)>& body, const Context* ctx) {
  if (n == 0) return;
  if (grain == 0) grain = 1;
  const std::size_t chunks = (n + grain - 1) / grain;
  const int threads = ctx != nullptr ? ctx->threads() : 0;
  auto run_chunk = [&](std::size_t c) {
    check_cancel(ctx);
    const std::size_t b = c * grain;
    const std::size_t e = b + grain < n ? b + grain : n;
    body(b, e);
  };
  if (threads == 1 || (ctx == nullptr && in_serial_loop)) {
    const SerialScope serial;
    for (std::size_t c = 0; c < chunks; ++c) run_chunk(c);
    return;
  }
  if (chunks == 1) {
    run_chunk(0);
    return;
  }
#if defined(RAMIFORM_PARALLEL_STD_THREADS)
  // The ThreadSanitizer build (`make tsan`): Debian's oneTBB is not instrumented, so the
  // synchronization inside it is invisible to TSan and every loop would look racy. Here plain
  // threads take the same fixed chunks from a shared counter and are joined; loops nested in a
  // chunk run serially on its thread. The chunks, and so the results, are those of oneTBB.
  const unsigned hardware = std::max(1U, std::thread::hardware_concurrency());
  const std::size_t workers =
      std::min<std::size_t>(chunks, threads > 1 ? static_cast<std::size_t>(threads) : hardware);
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
    const SerialScope serial;
    for (std::size_t c = next++; c < chunks && !failed.load(); c = next++) {
      try {
        run_chunk(c);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        failed.store(true);
      }
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  for (std::size_t w = 1; w < workers; ++w) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
#else
  auto run = [&] {
    // simple_partitioner with grain 1 over chunk indices: the chunk boundaries are fixed above,
    // only their assignment to threads varies.
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, chunks, 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t c = r.begin(); c != r.end(); ++c) run_chunk(c);
        },
        tbb::simple_partitioner());
  };
  if (threads > 1) {
    arena_for(threads).execute(run);
  } else {
    run();
  }
#endif
}

std::size_t exclusive_scan(std::vector<std::size_t>& counts) {
  std::size_t total = 0;
  for (auto& c : counts) {
    const std::size_t v = c;
    c = total;
    total += v;
  }
  return total;
}

}  // namespace ramiform::parallel
