#!/usr/bin/env bash
# `mvr render --backend vk --method multiview --views 8` writes 8 views (lavapipe: one a pass,
# src/vk/README.md), validation on, and with --shadows; `mvr info` names the device and its
# multiview limit; an unknown method is one `error:` line and exit 1. Skips (exit 77) without a
# Vulkan device unless MVR_REQUIRE_GL=1.
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
"$mvr" render --backend vk --method multiview --shadows --views 2 --size 160x120 -o "$out/sh" >/dev/null
for v in 0 1; do test -s "$out/sh/view-$v.png"; done
set +e
err=$("$mvr" render --backend vk --method gs-mrt --views 2 -o "$out/bad" 2>&1 >/dev/null)
rc=$?
set -e
[[ $rc == 1 ]] || { echo "expected exit 1, got $rc: $err" >&2; exit 1; }
grep -q "gs-mrt" <<<"$err" || { echo "the error does not name the method: $err" >&2; exit 1; }
[[ $(grep -c '^error:' <<<"$err") == 1 ]] || { echo "expected one error line: $err" >&2; exit 1; }
echo ok
