// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// `Context`: progress reporting, cancellation, the thread count and the memory budget of long
/// operations.
/// Every long operation takes `Context*`; nullptr costs nothing and means "all cores, no
/// progress, never cancelled". Operations check it once per chunk of work, never per sample.

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

namespace ramiform {

class Context {
 public:
  /// Called with a stage name and a fraction in [0, 1]; may be called from any thread.
  using ProgressFn = std::function<void(const std::string& stage, double fraction)>;

  static constexpr int kMaxThreads = 1024;  ///< most threads a caller may ask for

  Context() = default;
  /// `threads`: 0 (all cores) to kMaxThreads.
  explicit Context(int threads) : threads_(threads) {}

  /// Number of worker threads; 0 means all hardware threads. Results never depend on it.
  [[nodiscard]] int threads() const { return threads_; }
  void set_threads(int threads) { threads_ = threads; }

  /// The most memory, in bytes, a long operation may plan to use (core/memory.h); 0, the
  /// default, means the memory available on the machine when the operation starts.
  [[nodiscard]] std::uint64_t max_memory() const { return max_memory_; }
  void set_max_memory(std::uint64_t bytes) { max_memory_ = bytes; }

  void set_progress(ProgressFn fn) { progress_ = std::move(fn); }
  /// Reports progress (no-op without a callback).
  void report(const std::string& stage, double fraction) const {
    if (progress_) progress_(stage, fraction);
  }

  /// Requests cancellation; thread-safe.
  void cancel() { cancelled_.store(true, std::memory_order_relaxed); }
  [[nodiscard]] bool is_cancelled() const { return cancelled_.load(std::memory_order_relaxed); }
  /// Throws `Cancelled` if cancellation was requested.
  void check() const;

 private:
  int threads_ = 0;
  std::uint64_t max_memory_ = 0;
  ProgressFn progress_;
  std::atomic<bool> cancelled_{false};
};

/// Throws `Cancelled` when `ctx` is non-null and cancelled.
inline void check_cancel(const Context* ctx) {
  if (ctx != nullptr) ctx->check();
}

}  // namespace ramiform
