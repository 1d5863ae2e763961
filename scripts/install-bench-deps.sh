#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
# Installs the extra Debian packages of the optional benchmarks, if any are missing: OpenVDB for
# bench/bench_openvdb.cpp (MPL-2.0; linked into that benchmark only, never into the library).
# Safe to run repeatedly. The library, the CLI and `make test` never need these.
# libopenvdb-dev (10.0.1 on bookworm) does not depend on what its headers and its CMake module
# need: the Boost headers (openvdb/math/Math.h includes boost/numeric) and Boost.Iostreams
# (FindOpenVDB.cmake requires it), and log4cplus (FindOpenVDB.cmake requires it because
# libopenvdb links it). Hence the two extra packages.
set -euo pipefail

packages=(libopenvdb-dev libboost-iostreams-dev liblog4cplus-dev)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "ramiform: installing missing benchmark packages: ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then
  SUDO=()
elif command -v sudo >/dev/null 2>&1; then
  SUDO=(sudo)
else
  echo "ramiform: need root (or sudo) to install: ${missing[*]}" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" apt-get update -qq
"${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
