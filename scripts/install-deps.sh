#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
# Installs the Debian packages ramiform needs, if any are missing (`--bench`: also those of the
# optional OpenVDB comparison benchmark; `--fuzz`: also clang and libFuzzer for `make fuzz`),
# then the web tools of tools/web (the glTF validator and three.js, `npm ci`) and the studio page's
# packages in web/studio (Vite, CodeMirror, three.js) when npm exists.
# Safe to run repeatedly; quick when everything is there.
set -euo pipefail

packages=(build-essential cmake pkg-config libeigen3-dev libtbb-dev libnanoflann-dev
          libcli11-dev nlohmann-json3-dev libcairo2-dev libgtest-dev libgmock-dev libbenchmark-dev libhwy-dev
          # `ramiform studio`'s HTTP server (apps/ramiform/studio, docs/studio_api.md; MIT)
          libcpp-httplib-dev
          python3 python3-pytest python3-distributed
          # the Python module (python/, docs/python.md) and what its tests and examples use
          pybind11-dev python3-dev python3-numpy python3-scipy python3-matplotlib)

# `--bench`: also the optional comparison benchmark's OpenVDB (MPL-2.0; linked into
# bench/bench_openvdb.cpp only, never into the library; `make test` never needs it).
# libopenvdb-dev (10.0.1 on bookworm) does not depend on what its headers and CMake module need:
# Boost.Iostreams (FindOpenVDB.cmake requires it; the headers include Boost) and log4cplus
# (libopenvdb links it). Hence the two extra packages.
# Also Open3D's Python module for the reconstruction comparison (bench/compare_reconstruct.sh:
# screened Poisson reconstruction of the same points; MIT, used from Python only).
if [ "${1:-}" = "--bench" ]; then
  packages+=(libopenvdb-dev libboost-iostreams-dev liblog4cplus-dev python3-open3d)
fi

# `--fuzz`: Debian's clang 14 and its compiler-rt (libFuzzer, ASan and UBSan runtimes) for the
# fuzz harnesses of fuzz/ (docs/fuzzing.md); llvm-14 for llvm-symbolizer (readable stacks).
if [ "${1:-}" = "--fuzz" ]; then
  packages+=(clang-14 libclang-rt-14-dev llvm-14)
fi

# The .glb tests (tests/web, docs/viewing.md) run the Khronos glTF validator and three.js in
# Debian's headless Chromium, from node packages in tools/web. Without npm they skip, and so
# Chromium (about 45 s to install, 360 MB) is only installed where npm is.
if command -v npm >/dev/null 2>&1; then
  packages+=(chromium)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -gt 0 ]; then
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
fi

# `npm ci` in DIR (tools/web, web/studio), exactly as its package-lock.json pins it. A copy of the
# lock file inside node_modules marks a finished `npm ci`, so a second run does nothing. Without
# npm, or when `npm ci` fails (no registry), it warns and goes on: the C++ build does not need
# these packages, and the browser tests that do then skip.
#   npm_ci DIR WHAT WITHOUT   (WHAT: what it installs; WITHOUT: what happens without it)
npm_ci() {
  local dir="$root/$1" stamp="$root/$1/node_modules/.ramiform-package-lock.json"
  if ! command -v npm >/dev/null 2>&1; then
    echo "ramiform: npm not found: skipping $1 ($3)"
  elif ! cmp -s "$dir/package-lock.json" "$stamp"; then
    echo "ramiform: npm ci in $1 ($2)"
    if (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error); then
      cp "$dir/package-lock.json" "$stamp"
    else
      echo "ramiform: warning: npm ci in $1 failed: $3" >&2
    fi
  fi
}
root="$(cd "$(dirname "$0")/.." && pwd)"
# The glTF validator, three.js and playwright-core of the .glb tests (docs/viewing.md).
npm_ci tools/web "glTF validator, three.js, playwright-core" \
  "the .glb validator and render tests will skip"
# Vite, CodeMirror 6, three.js and playwright-core for the page of `ramiform studio`
# (docs/studio.md): the build runs `npm run build` there when node_modules exists and embeds
# web/studio/dist in the binary.
npm_ci web/studio "Vite, CodeMirror, three.js, playwright-core" \
  "ramiform studio will serve no page, and its browser test will skip"
