#!/usr/bin/env bash
# Builds the libFuzzer harnesses (clang, -fsanitize=fuzzer,address,undefined)
# into build-fuzz/ and runs each for a bounded time:
#   tests/fuzz/run.sh [SECONDS]     SECONDS in all, shared by the 5 harnesses (100)
# First the pinned regression inputs (tests/fuzz/regressions/<harness>/) run
# once each, then every harness mutates its seed corpus (tests/fuzz/corpus/
# <harness>/, read only; new inputs go to build-fuzz/corpus/<harness>/).
# A crash, sanitizer report, broken invariant, leak or timeout fails the run;
# the input is left in build-fuzz/artifacts/. Figures: build-fuzz/logs/.
# Bugs found but not fixed yet are pinned in tests/fuzz/open/<harness>/ (and
# as a Catch2 "[!shouldfail]" test); a failure whose message is listed in
# tests/fuzz/open/<harness>.signatures is reported as that open bug instead
# of failing the run, so the bounded run stays deterministic.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
total=${1:-100}
build=${FUZZ_BUILD_DIR:-build-fuzz}
harnesses=(read_obj read_off read_ply read_stl trace)
per=$(( total / ${#harnesses[@]} ))
# FUZZ_SEED fixes libFuzzer's random seed (CI: the same mutations every run,
# so a green build stays green; 0 = a new seed each run, for campaigns).
seed=${FUZZ_SEED:-0}
[ "$per" -ge 1 ] || per=1

CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DSUBDIVTRACE_BUILD_FUZZ=ON -DSUBDIVTRACE_BUILD_TESTS=OFF -DSUBDIVTRACE_BUILD_BENCH=OFF \
    -DSUBDIVTRACE_BUILD_POVRAY=OFF > "$build.configure.log" 2>&1 || { cat "$build.configure.log"; exit 1; }
rm -f "$build.configure.log"
cmake --build "$build" -j 2 --target fuzz

mkdir -p "$build/logs" "$build/artifacts"
export ASAN_OPTIONS=abort_on_error=1:detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1
status=0
for h in "${harnesses[@]}"; do
    bin="$build/fuzz/fuzz_$h"
    seeds="tests/fuzz/corpus/$h"
    work="$build/corpus/$h"
    mkdir -p "$work"
    dict=()
    [ -f "tests/fuzz/dict/$h.dict" ] && dict=("-dict=tests/fuzz/dict/$h.dict")
    log="$build/logs/$h.log"
    if [ -d "tests/fuzz/regressions/$h" ]; then
        if ! "$bin" "tests/fuzz/regressions/$h"/* > "$log.regressions" 2>&1; then
            echo "fuzz $h: a pinned regression input fails:"; tail -30 "$log.regressions"
            status=1
            continue
        fi
    fi
    if "$bin" "${dict[@]}" -seed="$seed" -max_total_time="$per" -timeout=10 -rss_limit_mb=2048 \
        -print_final_stats=1 -artifact_prefix="$build/artifacts/$h-" "$work" "$seeds" > "$log" 2>&1; then
        runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
        cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 || true)
        echo "fuzz $h: ${runs} executions in ${per} s, ${cov:-cov: ?}, no failure"
    else
        known=""
        if [ -f "tests/fuzz/open/$h.signatures" ]; then
            while IFS= read -r sig; do
                [ -n "$sig" ] && grep -qF -- "$sig" "$log" && known="$sig"
            done < "tests/fuzz/open/$h.signatures"
        fi
        if [ -n "$known" ]; then
            echo "fuzz $h: hit the open bug '$known' (tests/fuzz/open/$h/), not counted as a failure"
        else
            echo "fuzz $h: FAILED (input in $build/artifacts/, log $log):"
            grep -E "ERROR|invariant broken|what\(\)|SUMMARY|Test unit written" "$log" | head -20
            status=1
        fi
    fi
done
exit $status
