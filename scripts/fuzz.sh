#!/usr/bin/env bash
# Runs every libFuzzer target of a fuzz build (MVR_BUILD_FUZZERS, see tests/fuzz/) for a bounded
# time under ASan + UBSan, two at a time. Usage: scripts/fuzz.sh [BUILD_DIR] [SECONDS] [TARGET...]
# (defaults: build-fuzz, 30 s each, every mvr_fuzz_* program). Each target starts from its
# committed seeds (tests/fuzz/corpus/<name>, copied to a scratch corpus so the tree is left as
# it is) and its dictionary (tests/fuzz/dict/<name>.dict) if there is one.
# Runs vary as little as libFuzzer allows: every target starts from -seed=$FUZZ_SEED (default
# 1) and its seeds in sorted order, writes its inputs to one fixed path (/tmp/mvr-fuzz-<name>:
# the paths a reader sees feed libFuzzer's coverage and comparisons) and stops after the number
# of inputs tests/fuzz/runs gives it (about SECONDS on the 2-core machine it was measured on;
# SECONDS x 4 is the wall-clock cap), not after a time that depends on the machine. libFuzzer
# still drifts a little from run to run (two runs of 30 000 glTF inputs end a few edges apart),
# so a fault found in CI is found by a neighbouring path, not by a different campaign.
# FUZZ_SEED=0 (a random seed) and FUZZ_RUNS=0 (SECONDS each, no count) explore instead.
# A claim of more memory than any machine has (ASan's limit, 1 TiB) fails as it does in a
# release build: operator new throws std::bad_alloc (allocator_may_return_null=1), which the
# reader must turn into an error; an allocation over 2 GiB that could succeed fails the run.
# A crash, a sanitizer report, a leak, an input slower than 10 s or one needing more than 2 GiB
# fails the run; the input that did it is kept in BUILD_DIR/fuzz-artifacts/ (minimize it with
# `mvr_fuzz_<name> -minimize_crash=1 -runs=10000 FILE` and add it to regressions/<name>/).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-fuzz}
seconds=${2:-30}
shift $(($# > 2 ? 2 : $#))
targets=("$@")
if ((${#targets[@]} == 0)); then
    for t in "$build"/tests/fuzz/mvr_fuzz_*; do targets+=("${t##*/mvr_fuzz_}"); done
fi
src=$PWD/tests/fuzz
work=$PWD/$build/fuzz-work
artifacts=$PWD/$build/fuzz-artifacts
rm -rf "$work" "$artifacts"
mkdir -p "$work" "$artifacts"
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:symbolize=1:detect_stack_use_after_return=1:allocator_may_return_null=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/fuzz/lsan.supp}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}

run_one() {
    local name=$1 bin=$PWD/$build/tests/fuzz/mvr_fuzz_$1
    local corpus=$work/$name
    mkdir -p "$corpus"
    # Seeds only: the regression inputs (ctest runs them) include headers that claim huge
    # images, and every mutation of those would cost seconds instead of microseconds. They are
    # named in one sorted list (-seed_inputs) rather than read from a folder, whose listing
    # order is the file system's and would change the run; the corpus folder starts empty.
    local seeds=()
    if [[ -d $src/corpus/$name ]]; then
        seeds=(-seed_inputs="$(LC_ALL=C find "$src/corpus/$name" -type f | LC_ALL=C sort | paste -sd,)")
    fi

    local dict=()
    [[ -f $src/dict/$name.dict ]] && dict=(-dict="$src/dict/$name.dict")
    local runs=() limit=$seconds
    local n
    n=$(awk -v t="$name" '$1 == t { print $2 }' "$src/runs")
    if [[ ${FUZZ_RUNS:-1} != 0 && -n $n ]]; then
        runs=(-runs=$((n * seconds / 30)))
        limit=$((seconds * 4))
    fi
    local scratch=/tmp/mvr-fuzz-$name start=$SECONDS rc=0
    rm -rf "$scratch"
    (cd "$work" && MVR_FUZZ_SCRATCH=$scratch "$bin" "$corpus" "${seeds[@]}" "${dict[@]}" \
        -seed="${FUZZ_SEED:-1}" "${runs[@]}" -max_total_time="$limit" -timeout=10 \
        -rss_limit_mb=2048 -max_len=8192 -print_final_stats=1 \
        -artifact_prefix="$artifacts/$name-") >"$work/$name.log" 2>&1 || rc=$?
    rm -rf "$scratch"
    local execs
    execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$work/$name.log" | grep -o '[0-9]*$' || echo "?")
    if ((rc == 0)); then
        echo "fuzz: $name: ok, $execs inputs in $((SECONDS - start)) s, corpus $(ls "$corpus" | wc -l) files"
    else
        echo "fuzz: $name: FAILED (rc $rc) after $((SECONDS - start)) s; log: $work/$name.log"
        grep -E "ERROR|SUMMARY|runtime error|Test unit written|deadly signal|timeout" "$work/$name.log" | head -20
        return 1
    fi
}
export -f run_one
export build seconds src work artifacts
printf '%s\n' "${targets[@]}" | xargs -P 2 -I{} bash -c 'run_one {}' && status=0 || status=1
if ((status)); then
    echo "fuzz: failures; inputs in $artifacts:"
    ls -l "$artifacts"
fi
exit $status
