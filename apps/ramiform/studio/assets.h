// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// The studio page (web/studio/dist, built by Vite) embedded in the binary at build time by
// embed_assets.cmake: every file with its MIME type, or a one-page fallback when npm was missing.

#include <span>
#include <string_view>

namespace ramiform::studio {

struct StudioAsset {
  std::string_view path;  ///< "/index.html", "/assets/index-1a2b.js", ...
  std::string_view mime;  ///< the Content-Type it is served with
  std::span<const unsigned char> data;
};

/// Every embedded file, sorted by path.
[[nodiscard]] std::span<const StudioAsset> studio_assets();
/// False when the fallback page stands in for the unbuilt page.
[[nodiscard]] bool studio_page_built();

}  // namespace ramiform::studio
