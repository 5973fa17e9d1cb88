#!/usr/bin/env bash
# `mvr render --backend vk --method multiview --views 8` writes 8 views (lavapipe: batches of 6
# and 2), validation on; `mvr info` names the device and its multiview limit; an unsupported
# request is one `error:` line and exit 3. Skips (exit 77) without a Vulkan device unless
# MVR_REQUIRE_GL=1.
set -euo pipefail
mvr=$1
export MVR_VK_VALIDATION=1
info=$("$mvr" info 2>&1)
if ! grep -q "vk device: " <<<"$info"; then
    if [[ ${MVR_REQUIRE_GL:-} == 1 ]]; then echo "no vk device: $info" >&2; exit 1; fi
    echo "skip: no Vulkan device"; exit 77
fi
grep -q "maxMultiviewViewCount [0-9]" <<<"$info"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$mvr" render --backend vk --method multiview --views 8 --size 160x120 -o "$out/mv" >/dev/null
for v in 0 1 2 3 4 5 6 7; do test -s "$out/mv/view-$v.png"; done
test ! -e "$out/mv/view-8.png"
set +e
err=$("$mvr" render --backend vk --method multiview --shadows --views 2 -o "$out/sh" 2>&1 >/dev/null)
rc=$?
set -e
[[ $rc == 3 ]] || { echo "expected exit 3, got $rc: $err" >&2; exit 1; }
[[ $(grep -c '^error:' <<<"$err") == 1 ]] || { echo "expected one error line: $err" >&2; exit 1; }
echo ok
