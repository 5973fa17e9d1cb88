#!/usr/bin/env bash
# CI beyond scripts/test.sh (the Release build and its tests), each part timed; .ci/run runs it
# after scripts/test.sh. Each part builds only what its tests need:
#  1. asan (build-asan): gcc with -DMVR_SANITIZE=address,undefined at -O1 -g1 (line tables
#     for the reports' stacks; -O2 and full debug info cost build time and catch nothing more),
#     every library, `mvr` and the test programs of the unit and CLI tests
#     (`ctest -L 'unit|cli'`, fuzz seeds and regression inputs included). Not built: the GL
#     tests, the viewer, the micro benchmarks and the Python module (no unit or CLI test runs
#     them; the Release build does). Any UBSan report is fatal.
#  2. scalar (build-scalar): Release with -DMVR_SIMD=scalar. MVR_SIMD changes only mvr_raster
#     (the soft backend's kernels), so only the unit tests that render through it are built and
#     run: raster (SIMD == scalar, unified == multipass), shadows, backends (framing),
#     conformance (every soft method against multipass) and golden (the exact reference
#     images). The others (core, composite, adelson, bench harness, fuzz seeds, install) do not
#     link mvr_raster: their scalar build would be the Release build again.
#  3. fuzz (build-fuzz): clang + libFuzzer at -O1 -g1, only the fuzz targets (`mvr_fuzzers`:
#     core, scene_io, composite, mvr_camera_path), every reader's target over its seeds once, then each for
#     FUZZ_SECONDS (default 30) under ASan + UBSan, two at a time (scripts/fuzz.sh).
# Usage: scripts/ci-extra.sh [asan|scalar|fuzz ...] (default: all three). Compiler launchers
# (ccache) are whatever the environment's CMAKE_<LANG>_COMPILER_LAUNCHER says; CI has none.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
export MVR_SHARED_DIR="${MVR_SHARED_DIR:-$(cd .. && pwd)/shared}"
jobs=$(nproc)
parts=("$@")
((${#parts[@]})) || parts=(asan scalar fuzz)
summary=()
total=$SECONDS

timed() {  # timed NAME COMMAND...: runs it, records its wall time
    local name=$1 start=$SECONDS
    shift
    echo "ci-extra: == $name ($(uptime | sed 's/.*load/load/'))"
    "$@"
    summary+=("$name: $((SECONDS - start)) s")
    echo "ci-extra: $name took $((SECONDS - start)) s"
}

configure() {  # configure DIR CMAKE_ARGS...
    local dir=$1
    shift
    cmake -S . -B "$dir" -DMVR_SHARED_DIR="$MVR_SHARED_DIR" "$@" >/dev/null
}
export -f configure
export jobs

# -O1 -g1: the sanitizer builds' flags (RelWithDebInfo's slot, NDEBUG kept as in Release).
quick=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
       "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG")

for part in "${parts[@]}"; do
    case $part in
    asan)
        timed "asan build" bash -c 'configure build-asan "$@" && cmake --build build-asan -j$jobs' \
            _ "${quick[@]}" -DMVR_SANITIZE=address,undefined -DMVR_BUILD_GL_TESTS=OFF \
            -DMVR_BUILD_VIEWER=OFF -DMVR_BUILD_BENCH=OFF -DMVR_BUILD_PYTHON=OFF
        # LeakSanitizer: leaks allocated inside Debian's libraries are suppressed by
        # tests/fuzz/lsan.supp (assimp's error paths). The processes that load Mesa's llvmpipe
        # (GL-rendering CLI tests) are rerun with detect_leaks=0 instead of getting
        # suppressions: there LSan reports no leak that a suppression could name, it dies at
        # exit while llvmpipe's threads still run, so no suppression file helps. The same for
        # those that load lavapipe (the vk backend, listed by every registry loop: shadows,
        # auto, `mvr info`): 128-240 bytes from a Vulkan module already unloaded at exit
        # ("<unknown module>"), nothing a suppression can name. The rerun
        # keeps ASan and UBSan on and names each test that needed it in the log.
        timed "asan tests" bash -c "cd build-asan && export \
            LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp \
            UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 && \
            if ! ASAN_OPTIONS=detect_leaks=1:detect_stack_use_after_return=1 \
                ctest --output-on-failure --timeout 1800 -j$jobs -L 'unit|cli' >asan-tests.log; then \
                grep -E 'Failed|Exception|SEGFAULT' asan-tests.log | tee asan-rerun.txt; \
                ASAN_OPTIONS=detect_leaks=0 ctest --output-on-failure --timeout 1800 \
                    --rerun-failed -j$jobs && \
                echo 'ci-extra: passed with detect_leaks=0 only (llvmpipe / lavapipe processes):' && \
                cat asan-rerun.txt; \
            fi && tail -3 asan-tests.log"
        ;;
    scalar)
        timed "scalar build" bash -c 'configure build-scalar "$@" && cmake --build build-scalar \
            -j$jobs --target mvr_raster_tests mvr_shadows_tests mvr_backends_tests \
            mvr_conformance_tests mvr_golden_tests' _ -DCMAKE_BUILD_TYPE=Release \
            -DMVR_SIMD=scalar -DMVR_BUILD_GL_TESTS=OFF -DMVR_BUILD_VIEWER=OFF \
            -DMVR_BUILD_BENCH=OFF -DMVR_BUILD_PYTHON=OFF
        # -L unit minus the folders' programs not built here: their placeholder tests
        # (NAME_NOT_BUILT) carry no label; fuzz and install are add_test()s of their own.
        timed "scalar tests" bash -c "cd build-scalar && \
            ctest --output-on-failure --timeout 900 -j$jobs -L unit -LE 'fuzz|install'"
        ;;
    fuzz)
        timed "fuzz build" bash -c 'configure build-fuzz "$@" && \
            cmake --build build-fuzz -j$jobs --target mvr_fuzzers' _ "${quick[@]}" \
            -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DMVR_BUILD_FUZZERS=ON \
            -DMVR_BUILD_VIEWER=OFF -DMVR_BUILD_BENCH=OFF -DMVR_BUILD_PYTHON=OFF
        timed "fuzz seeds" bash -c "cd build-fuzz && ctest --output-on-failure -j$jobs -L fuzz"
        timed "fuzz run" scripts/fuzz.sh build-fuzz "${FUZZ_SECONDS:-30}"
        ;;
    *)
        echo "ci-extra: unknown part '$part' (asan, scalar, fuzz)" >&2
        exit 1
        ;;
    esac
done
echo "ci-extra: all passed in $((SECONDS - total)) s"
printf 'ci-extra:   %s\n' "${summary[@]}"
