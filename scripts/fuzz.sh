#!/usr/bin/env bash
# Runs every libFuzzer target of a fuzz build (MVR_BUILD_FUZZERS, see tests/fuzz/) for a bounded
# time under ASan + UBSan, two at a time. Usage: scripts/fuzz.sh [BUILD_DIR] [SECONDS] [TARGET...]
# (defaults: build-fuzz, 30 s each, every mvr_fuzz_* program). Each target starts from its
# committed seeds (tests/fuzz/corpus/<name>, copied to a scratch corpus so the tree is left as
# it is) and its dictionary (tests/fuzz/dict/<name>.dict) if there is one.
# Runs are reproducible: every target starts from libFuzzer's -seed=$FUZZ_SEED (default 1, so a
# CI run explores the inputs the last verified run explored, and a red CI is never luck);
# FUZZ_SEED=0 lets libFuzzer pick a random seed per run, for exploring.
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
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:symbolize=1:detect_stack_use_after_return=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/fuzz/lsan.supp}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}

run_one() {
    local name=$1 bin=$PWD/$build/tests/fuzz/mvr_fuzz_$1
    local corpus=$work/$name
    mkdir -p "$corpus"
    # Seeds only: the regression inputs (ctest runs them) include headers that claim huge
    # images, and every mutation of those would cost seconds instead of microseconds.
    [[ -d $src/corpus/$name ]] && cp "$src/corpus/$name"/* "$corpus"/

    local dict=()
    [[ -f $src/dict/$name.dict ]] && dict=(-dict="$src/dict/$name.dict")
    local start=$SECONDS rc=0
    (cd "$work" && "$bin" "$corpus" "${dict[@]}" -seed="${FUZZ_SEED:-1}" \
        -max_total_time="$seconds" -timeout=10 \
        -rss_limit_mb=2048 -max_len=8192 -print_final_stats=1 \
        -artifact_prefix="$artifacts/$name-") >"$work/$name.log" 2>&1 || rc=$?
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
