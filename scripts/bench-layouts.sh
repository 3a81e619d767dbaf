#!/usr/bin/env bash
# Runs the culling benchmark on the four layouts of docs/BENCHMARKS.md ("Culling where students
# look"): the default layout, the skull shown, the left hemisphere's cortex faded to 0.4, and a
# coronal cut. Writes each run's JSON and per-frame CSV to OUT (default docs/bench-layouts).
#   scripts/bench-layouts.sh [OUT] [FRAMES] [target/release/vbrain]
set -euo pipefail
cd "$(dirname "$0")/.."
OUT="${1:-docs/bench-layouts}"
FRAMES="${2:-120}"
VBRAIN="${3:-target/release/vbrain}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
LOBES=()
for lobe in "Frontal lobe" "Parietal lobe" "Temporal lobe" "Occipital lobe" "Cingulate gyrus" "Insula"; do
    LOBES+=("Cerebrum/Left hemisphere/$lobe=0.4")
done
run() {
    local name="$1"
    shift
    "$VBRAIN" bench organs/brain --frames "$FRAMES" --size 512x512 --cull none,occlusion --json --out "$TMP/$name" "$@" \
        >"$TMP/$name.json"
    mkdir -p "$OUT"
    # The JSON names the files it wrote: the CSV where it lands; the plot is not kept.
    sed -e "s|$TMP/$name/bench.csv|$name.csv|" -e '/"plot": /d' "$TMP/$name.json" >"$OUT/$name.json"
    cp "$TMP/$name/bench.csv" "$OUT/$name.csv"
    echo "$name: $(grep -o '"hidden_leaves_culled_percent": [0-9.]*' "$OUT/$name.json" | tail -1)"
}
run default
run skull --show skull
run faded --opacity "${LOBES[@]}"
run cut --clip coronal=0
