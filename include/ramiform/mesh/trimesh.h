// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Deprecated: `TriMesh` and `PointSet` moved to ramiform/core/geometry.h (every stage shares
/// them). This header stays for one release so that code written against 0.1 keeps compiling;
/// include ramiform/core/geometry.h instead.

#include "ramiform/core/geometry.h"
