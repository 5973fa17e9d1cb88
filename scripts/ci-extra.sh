#!/usr/bin/env bash
# CI beyond scripts/test.sh (the Release build and its tests), each part timed:
#  1. build-asan: gcc with -DMVR_SANITIZE=address,undefined, the unit and CLI tests
#     (`ctest -L 'unit|cli'`), any UBSan report fatal;
#  2. build-scalar: -DMVR_SIMD=scalar (the soft backend without SIMD paths), the unit tests;
#  3. build-fuzz: clang + libFuzzer, every reader's fuzz target for a bounded time under
#     ASan + UBSan (scripts/fuzz.sh; FUZZ_SECONDS per target, default 45, two at a time).
# Usage: scripts/ci-extra.sh [asan|scalar|fuzz ...] (default: all three).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
export MVR_SHARED_DIR="${MVR_SHARED_DIR:-$(cd .. && pwd)/shared}"
jobs=$(nproc)
parts=("$@")
((${#parts[@]})) || parts=(asan scalar fuzz)
summary=()

timed() {  # timed NAME COMMAND...: runs it, records its wall time
    local name=$1 start=$SECONDS
    shift
    echo "ci-extra: == $name"
    "$@"
    summary+=("$name: $((SECONDS - start)) s")
    echo "ci-extra: $name took $((SECONDS - start)) s"
}

configure() {  # configure DIR CMAKE_ARGS...
    local dir=$1
    shift
    cmake -S . -B "$dir" -DMVR_SHARED_DIR="$MVR_SHARED_DIR" "$@" >/dev/null
}

for part in "${parts[@]}"; do
    case $part in
    asan)
        timed "asan build" bash -c "$(declare -f configure); configure build-asan \
            -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMVR_SANITIZE=address,undefined && \
            cmake --build build-asan -j$jobs"
        # LeakSanitizer: leaks allocated inside Debian's libraries are suppressed by
        # tests/fuzz/lsan.supp (assimp's error paths). The processes that load Mesa's llvmpipe
        # (GL, viewer and GL-rendering CLI tests) are rerun with detect_leaks=0 instead of
        # getting suppressions: there LSan reports no leak that a suppression could name, it
        # dies at exit while llvmpipe's threads still run, so no suppression file helps. The
        # rerun keeps ASan and UBSan on and names each test that needed it in the log.
        timed "asan tests" bash -c "cd build-asan && export \
            LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp \
            UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 && \
            if ! ASAN_OPTIONS=detect_leaks=1:detect_stack_use_after_return=1 \
                ctest --output-on-failure --timeout 1800 -j$jobs -L 'unit|cli' >asan-tests.log; then \
                grep -E 'Failed|Exception|SEGFAULT' asan-tests.log | tee asan-rerun.txt; \
                ASAN_OPTIONS=detect_leaks=0 ctest --output-on-failure --timeout 1800 \
                    --rerun-failed -j$jobs && \
                echo 'ci-extra: passed with detect_leaks=0 only (llvmpipe processes):' && \
                cat asan-rerun.txt; \
            fi && tail -3 asan-tests.log"
        ;;
    scalar)
        timed "scalar build" bash -c "$(declare -f configure); configure build-scalar \
            -DCMAKE_BUILD_TYPE=Release -DMVR_SIMD=scalar -DMVR_BUILD_VIEWER=OFF && \
            cmake --build build-scalar -j$jobs"
        timed "scalar tests" bash -c "cd build-scalar && \
            ctest --output-on-failure --timeout 900 -j$jobs -L unit"
        ;;
    fuzz)
        timed "fuzz build" bash -c "$(declare -f configure); configure build-fuzz \
            -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
            -DCMAKE_CXX_COMPILER=clang++ -DMVR_BUILD_FUZZERS=ON && \
            cmake --build build-fuzz -j$jobs --target mvr_fuzzers"
        timed "fuzz corpora" bash -c "cd build-fuzz && ctest --output-on-failure -L fuzz"
        timed "fuzz run" scripts/fuzz.sh build-fuzz "${FUZZ_SECONDS:-45}"
        ;;
    *)
        echo "ci-extra: unknown part '$part' (asan, scalar, fuzz)" >&2
        exit 1
        ;;
    esac
done
echo "ci-extra: all passed"
printf 'ci-extra:   %s\n' "${summary[@]}"
