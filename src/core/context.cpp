// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/core/context.h"

#include "ramiform/core/errors.h"

namespace ramiform {

void Context::check() const {
  if (is_cancelled()) throw Cancelled();
}

}  // namespace ramiform
