#!/bin/bash
# Fuzzes the readers with libFuzzer (issue 16): scripts/fuzz.sh SECONDS [scene|msh|dat|json|vtu ...]
# Builds the fuzz targets with clang, AddressSanitizer and UBSan in build-fuzz/ (needs clang,
# libclang-rt-dev and libomp-dev from Debian), seeds each reader's corpus with the examples'
# files and the inputs kept for it, and runs it for SECONDS (json: study.json and summary.json;
# vtu: the VTU reader of plot). An input that crashes or hangs is written to
# tests/fuzz/regressions/<reader>/, which the fuzz_regression_tests replay in CTest: fix the
# reader, keep the input. Prints each reader's executions and coverage. C2D_FUZZ_JOBS sets the
# build's parallel jobs (default 2).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:?usage: scripts/fuzz.sh SECONDS [scene|msh|dat|json|vtu ...]}
shift
readers=("$@")
[ ${#readers[@]} -eq 0 ] && readers=(scene msh dat json vtu)
build="${C2D_FUZZ_BUILD:-$root/build-fuzz}"
if [ ! -f "$build/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DC2D_FUZZ=ON -DC2D_SANITIZE=ON > "$build.configure.log" 2>&1 ||
    { echo "fuzz: configure failed, see $build.configure.log" >&2; exit 1; }
fi
targets=()
for r in "${readers[@]}"; do targets+=("fuzz_$r"); done
cmake --build "$build" -j"${C2D_FUZZ_JOBS:-2}" --target "${targets[@]}" > "$build.build.log" 2>&1 ||
  { echo "fuzz: build failed, see $build.build.log" >&2; exit 1; }
declare -A extension=([scene]=toml [msh]=msh [dat]=dat [json]=json [vtu]=vtu)
status=0
for r in "${readers[@]}"; do
  corpus="$build/corpus/$r"
  kept="$root/tests/fuzz/regressions/$r"
  mkdir -p "$corpus" "$kept"
  find "$root/examples" "$kept" -name "*.${extension[$r]}" -exec cp -n {} "$corpus/" \;
  log="$build/fuzz_$r.log"
  # -timeout: an input taking 10 s is a hang; -rss_limit_mb bounds a runaway allocation.
  # detect_leaks=0: gmsh's MSH4 reader leaks on some inputs it rejects (its own code, reported
  # at exit against whichever input ran last), which would stop the run with no input to blame.
  if ! ASAN_OPTIONS=detect_leaks=0 TMPDIR="$build" "$build/tests/fuzz_$r" -max_total_time="$seconds" -timeout=10 \
      -rss_limit_mb=2048 -artifact_prefix="$kept/" -print_final_stats=1 "$corpus" > "$log" 2>&1; then
    status=1
    echo "fuzz_$r: FOUND A CRASH OR HANG (input kept in $kept; log $log)"
  fi
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo '?')
  echo "fuzz_$r: ${seconds} s, $execs executions, coverage $cov edges"
done
exit $status
