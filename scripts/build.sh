#!/usr/bin/env bash
# Configures (once) and builds contact2d into ./build. Incremental, and quiet unless something fails.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${C2D_BUILD_DIR:-$root/build}"
mkdir -p "$build"
log="$build/build.log"
if [ ! -f "$build/CMakeCache.txt" ]; then
  if ! cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >"$log" 2>&1; then
    cat "$log" >&2; echo "build: configure failed (log: $log)" >&2; exit 1
  fi
fi
if ! cmake --build "$build" -j"$(nproc)" >"$log" 2>&1; then
  grep -E -A3 "error" "$log" | head -60 >&2 || true
  echo "build: compilation failed (full log: $log)" >&2; exit 1
fi
if grep -q "warning:" "$log"; then grep "warning:" "$log" >&2; fi
