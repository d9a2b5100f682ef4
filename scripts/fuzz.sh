#!/usr/bin/env bash
# Long fuzzing (docs/fuzzing.md; not part of CI, which only replays the corpus as FuzzReplay.* tests).
# Usage: scripts/fuzz.sh [SECONDS] [TARGET...]
#   Builds the libFuzzer targets with clang (-fsanitize=fuzzer,address,undefined) into build-fuzz/, runs each
#   TARGET (default: all) for SECONDS (default 600) and merges the inputs that add coverage into
#   fuzz/corpus/<target>/ (-merge=1, inputs ≤ FUZZ_MAX_LEN bytes). Crash/leak/timeout inputs are kept in
#   build-fuzz/artifacts/<target>/; the logs in build-fuzz/logs/. Exit status 1 when any target found something.
# Environment: FUZZ_PARALLEL (targets run at once, default 1), FUZZ_NICE (nice level, default 10),
#   FUZZ_MAX_LEN (default 4096), FUZZ_BUILD_JOBS (ninja -j, default 2).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
all_targets=(datagram control level basis_cache mesh)
seconds=${1:-600}
[[ $# -gt 0 ]] && shift
targets=("$@")
[[ ${#targets[@]} -eq 0 ]] && targets=("${all_targets[@]}")
parallel=${FUZZ_PARALLEL:-1}
niceness=${FUZZ_NICE:-10}
max_len=${FUZZ_MAX_LEN:-4096}
build="$root/build-fuzz"

# -O1 with line tables (the usual libFuzzer trade: fast enough, readable stacks); asserts stay on (no NDEBUG).
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=None \
  -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" \
  -DSHAPECAST_FUZZ=ON -DSHAPECAST_BUILD_TESTS=OFF -DSHAPECAST_BUILD_BENCH=OFF >/dev/null
nice -n "$niceness" ninja -C "$build" -j"${FUZZ_BUILD_JOBS:-2}" "${targets[@]/#/fuzz_}"

# Leaks are findings (detect_leaks=1); UB aborts (the build has -fno-sanitize-recover=undefined).
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:allocator_may_return_null=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export OPENBLAS_NUM_THREADS=1

# fuzz_one TARGET: runs it, merges its new inputs into the corpus, prints one summary line.
fuzz_one() {
  local target=$1 corpus="$root/fuzz/corpus/$1" fresh="$build/new-inputs/$1" log="$build/logs/$1.log"
  local artifacts="$build/artifacts/$1/" status=0
  rm -rf "$fresh" && mkdir -p "$fresh" "$artifacts" "$build/logs" "$corpus"
  local before
  before=$(find "$corpus" -type f | wc -l)
  local started=$SECONDS
  # New inputs go to $fresh (first folder); the kept corpus is only read.
  nice -n "$niceness" "$build/fuzz/fuzz_$target" -max_total_time="$seconds" -max_len="$max_len" -timeout=25 \
    -rss_limit_mb=4096 -print_final_stats=1 -artifact_prefix="$artifacts" "$fresh" "$corpus" >"$log" 2>&1 ||
    status=$?
  local elapsed=$((SECONDS - started))
  nice -n "$niceness" "$build/fuzz/fuzz_$target" -merge=1 -max_len="$max_len" "$corpus" "$fresh" \
    >>"$log" 2>&1 || true
  local runs after
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  after=$(find "$corpus" -type f | wc -l)
  printf '%-12s status %-3s seconds %-5s executions %-10s corpus %s -> %s files (%s KiB)  artifacts: %s\n' \
    "$target" "$status" "$elapsed" "${runs:-?}" "$before" "$after" "$(du -sk --apparent-size "$corpus" | cut -f1)" \
    "$(find "$artifacts" -type f | wc -l)"
  return "$status"
}

failed=0
running=0
for target in "${targets[@]}"; do
  fuzz_one "$target" &
  running=$((running + 1))
  if [[ $running -ge $parallel ]]; then
    wait -n || failed=1
    running=$((running - 1))
  fi
done
while [[ $running -gt 0 ]]; do
  wait -n || failed=1
  running=$((running - 1))
done
echo "machine: $(nproc) cores, $(sed -n 's/^model name\t*: //p' /proc/cpuinfo | head -1)"
exit "$failed"
