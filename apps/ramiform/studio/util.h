// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Small helpers of the studio server: tokens, paths, URLs.

#include <filesystem>
#include <string>
#include <string_view>

namespace ramiform::studio {

/// 32 lowercase hex characters from /dev/urandom (Failure when it cannot be read).
[[nodiscard]] std::string random_token();
/// a == b in time that depends only on their lengths.
[[nodiscard]] bool same_token(std::string_view a, std::string_view b);
/// The extension of `path` in lower case with its dot ("" without one).
[[nodiscard]] std::string lower_ext(const std::string& path);
/// A whole decimal number in [0, 2^31) and nothing else.
[[nodiscard]] bool parse_int(std::string_view text, int& value);
/// Percent-encodes every byte of a relative path except unreserved characters and '/'.
[[nodiscard]] std::string url_encode_path(std::string_view path);
/// True when the (canonical) `path` is `base` or lies below it.
[[nodiscard]] bool inside(const std::filesystem::path& path, const std::filesystem::path& base);

}  // namespace ramiform::studio
