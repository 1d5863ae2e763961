// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// `ramiform studio`'s HTTP server (docs/studio_api.md): the page embedded in the binary and the
// JSON API over Debian's cpp-httplib, on loopback unless told otherwise. Every request needs the
// access token (cookie or X-Ramiform-Token header); Host and Origin must name the server itself
// (no DNS rebinding, no cross-site requests); bodies are limited.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

namespace ramiform::studio {

struct StudioOptions {
  std::string script_path;  ///< the script shown first; empty: the demo crown (examples/demo.rf)
  std::string demo_script;  ///< the demo's text (used without script_path)
  std::filesystem::path out_dir = "studio-out";
  std::string listen = "127.0.0.1";
  int port = 8765;  ///< 0: any free port
  double run_timeout = 300;
  std::uint64_t max_memory = 0;
  int threads = 0;
  std::string token;  ///< empty: a random one
  std::string version = "ramiform";
};

/// Most bytes of a request body (413 beyond).
inline constexpr std::size_t kMaxBody = std::size_t{4} << 20;
/// Most bytes of a script (413 beyond).
inline constexpr std::size_t kMaxScript = std::size_t{1} << 20;

class StudioServer {
 public:
  /// Reads the script, creates OUT; throws InvalidArgument / InputError.
  explicit StudioServer(StudioOptions options);
  ~StudioServer();
  StudioServer(const StudioServer&) = delete;
  StudioServer& operator=(const StudioServer&) = delete;

  /// Binds and serves in a background thread; returns the port (Failure when it cannot bind).
  int start();
  /// Stops serving and ends every run.
  void stop();

  [[nodiscard]] const std::string& token() const;
  /// "http://127.0.0.1:PORT/?token=TOKEN".
  [[nodiscard]] std::string url() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace ramiform::studio
