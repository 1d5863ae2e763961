// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// File text in error messages, shared by every reader (io, the props files of sample, the
/// scene language): bytes shown so that a message about a binary or mis-encoded file says what
/// is there and cannot send control sequences to a terminal, and the byte order mark that some
/// editors and spreadsheets put at the start of text files.

#include <cstddef>
#include <string>
#include <string_view>

namespace ramiform {

/// The text with every byte outside printable ASCII (control characters, DEL, bytes >= 0x80)
/// written as "\xNN" (lower-case hex): an invisible byte order mark shows as "\xef\xbb\xbf".
/// With `max_chars`, the output stops with "..." once it holds that many characters (whole
/// escapes only).
[[nodiscard]] std::string printable_text(std::string_view text,
                                         std::size_t max_chars = std::string_view::npos);

/// printable_text() in single quotes, shortened to its first `max_chars - 3` bytes and "..."
/// when the text is longer than `max_chars` bytes (a line can be megabytes).
[[nodiscard]] std::string quoted_text(std::string_view text, std::size_t max_chars = 40);

/// The text without a leading UTF-8 byte order mark (EF BB BF).
[[nodiscard]] std::string_view skip_utf8_bom(std::string_view text);

}  // namespace ramiform
