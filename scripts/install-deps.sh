#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
# Installs the Debian packages ramiform needs, if any are missing (`--bench`: also those of the
# optional OpenVDB comparison benchmark; `--fuzz`: also clang and libFuzzer for `make fuzz`).
# Safe to run repeatedly.
set -euo pipefail

packages=(build-essential cmake pkg-config libeigen3-dev libtbb-dev libnanoflann-dev
          libcli11-dev nlohmann-json3-dev libgtest-dev libgmock-dev libbenchmark-dev libhwy-dev
          python3)

# `--bench`: also the optional comparison benchmark's OpenVDB (MPL-2.0; linked into
# bench/bench_openvdb.cpp only, never into the library; `make test` never needs it).
# libopenvdb-dev (10.0.1 on bookworm) does not depend on what its headers and CMake module need:
# Boost.Iostreams (FindOpenVDB.cmake requires it; the headers include Boost) and log4cplus
# (libopenvdb links it). Hence the two extra packages.
if [ "${1:-}" = "--bench" ]; then
  packages+=(libopenvdb-dev libboost-iostreams-dev liblog4cplus-dev)
fi

# `--fuzz`: Debian's clang 14 and its compiler-rt (libFuzzer, ASan and UBSan runtimes) for the
# fuzz harnesses of fuzz/ (docs/fuzzing.md); llvm-14 for llvm-symbolizer (readable stacks).
if [ "${1:-}" = "--fuzz" ]; then
  packages+=(clang-14 libclang-rt-14-dev llvm-14)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "ramiform: installing missing packages: ${missing[*]}"
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
