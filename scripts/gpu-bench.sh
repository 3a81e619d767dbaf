#!/usr/bin/env bash
# Culling on this machine's GPU (a real one, or Mesa's software one): the four layouts of
# docs/BENCHMARKS.md ("Culling where students look": default, skull shown, left cortex faded,
# coronal cut) on the default brain and on a 10x denser copy (`vbrain scale`), each with no
# culling, frustum culling and occlusion culling. Per run the bench's summary: median frame, cull
# and GPU time (where the adapter has timestamp queries), triangles drawn, and the draw time per
# triangle at which occlusion culling stops paying against what this GPU takes. One JSON file.
#   scripts/gpu-bench.sh [OUT.json] [FRAMES] [VBRAIN]
set -euo pipefail
cd "$(dirname "$0")/.."
OUT="${1:-gpu-bench.json}"
FRAMES="${2:-60}"
VBRAIN="${3:-target/release/vbrain}"
if [ ! -x "$VBRAIN" ]; then
    cargo build --release --locked -p vbrain-ui
fi
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
"$VBRAIN" scale organs/brain --factor 10 --out "$TMP/dense" --json >/dev/null
LOBES=()
for lobe in "Frontal lobe" "Parietal lobe" "Temporal lobe" "Occipital lobe" "Cingulate gyrus" "Insula"; do
    LOBES+=("Cerebrum/Left hemisphere/$lobe=0.4")
done
run() {
    local set="$1" layout="$2"
    shift 2
    "$VBRAIN" bench "$set" --frames "$FRAMES" --size 512x512 --cull none,frustum,occlusion --json \
        --out "$TMP/out-$(basename "$set")-$layout" "$@" >"$TMP/$(basename "$set")-$layout.json"
    echo "$(basename "$set") $layout: done" >&2
}
for set in organs/brain "$TMP/dense"; do
    run "$set" default
    run "$set" skull --show skull
    run "$set" faded --opacity "${LOBES[@]}"
    run "$set" cut --clip coronal=0
done
{
    printf '{\n  "frames": %s,\n  "size": [512, 512],\n  "runs": {\n' "$FRAMES"
    first=1
    for f in "$TMP"/*.json; do
        name="$(basename "$f" .json)"
        [ $first = 1 ] || printf ',\n'
        first=0
        # The bench's own paths point into a temporary folder: left out.
        printf '    "%s": ' "$name"
        grep -v -e '"csv":' -e '"plot":' "$f" | sed -e 's/^/    /' -e '1s/^    //'
    done
    printf '\n  }\n}\n'
} >"$OUT"
echo "wrote $OUT" >&2
