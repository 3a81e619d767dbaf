#!/usr/bin/env bash
# Renders the pictures in README.md and docs/ from the default brain (docs/viewer.png is a screenshot
# of the viewer under Xvfb, taken by hand). Needs ImageMagick's `convert` for the side-by-side figure.
#   scripts/docs-pictures.sh [target/release/vbrain]
set -euo pipefail
cd "$(dirname "$0")/.."
VBRAIN="${1:-target/release/vbrain}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
"$VBRAIN" render organs/brain --out docs/brain.png --size 640x480 --orbit=-55,15 >/dev/null
"$VBRAIN" render organs/brain --out "$TMP/coronal.png" --size 480x400 --clip coronal=-8 --orbit=-20,10 >/dev/null
"$VBRAIN" render organs/brain --out "$TMP/sagittal.png" --size 480x400 --clip sagittal=-4 --view right >/dev/null
convert "$TMP/coronal.png" "$TMP/sagittal.png" +append docs/sections.png
"$VBRAIN" render organs/brain --out docs/labels.png --size 960x720 --clip sagittal=-4 --view right --labels all >/dev/null
"$VBRAIN" render organs/brain --out docs/cull-debug.png --size 768x768 --orbit 30,15 --show skull --debug-culled >/dev/null
FADED=(--orbit=-90,5 --hide brainstem --opacity "Left hemisphere/Frontal lobe=0.35" "Left hemisphere/Parietal lobe=0.5"
    "Left hemisphere/Temporal lobe=0.45" "Left hemisphere/Occipital lobe=0.55")
for mode in alpha-sorted screendoor exact; do
    "$VBRAIN" render organs/brain --out "$TMP/$mode.png" --size 320x320 "${FADED[@]}" --transparency "$mode" >/dev/null
done
convert "$TMP/alpha-sorted.png" "$TMP/screendoor.png" "$TMP/exact.png" +append docs/transparency.png
