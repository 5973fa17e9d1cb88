#!/bin/sh
# tests/layering/check_layering.sh SOURCE_DIR — the layering rule (docs/architecture.md): no
# library includes a header of a library above it. core includes only mvr/core/; io only
# mvr/core/ and mvr/io/; composite nothing of gl, backends, session. Fails listing offenders.
set -u
src="$1"
bad=0
check() {  # check DIR ALLOWED_REGEX: every #include "mvr/..." under DIR must match ALLOWED_REGEX
    dirs="$1"; allowed="$2"
    hits=$(grep -rnE '^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"]mvr/' $dirs 2>/dev/null |
           grep -vE "[<\"]mvr/($allowed)/" || true)
    if [ -n "$hits" ]; then
        echo "layering violation in $dirs (allowed: mvr/{$allowed}/):"; echo "$hits"; bad=1
    fi
}
check "$src/src/core $src/include/mvr/core" "core"
check "$src/src/io $src/include/mvr/io" "core|io"
check "$src/src/composite $src/include/mvr/composite" "core|io|composite"
# third-party file libraries stay out of core
libs=$(grep -rnE '#[[:space:]]*include[[:space:]]*<(png\.h|jpeglib\.h|assimp/|meshoptimizer\.h|nlohmann/)' \
       "$src/src/core" "$src/include/mvr/core" || true)
if [ -n "$libs" ]; then echo "file/codec libraries included in core:"; echo "$libs"; bad=1; fi
[ $bad -eq 0 ] && echo "layering OK"
exit $bad
