#!/usr/bin/env bash
# The encoding benchmark of docs/BENCHMARKS.md: an 8-second 1280x720 turntable at 30 fps of the
# default brain, its 240 frames rendered alone, then written as GIF and as MP4, in one run.
# Usage: scripts/bench-video.sh [OUT_DIR]  (release build; MP4 needs ffmpeg)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-target/bench-video}
mkdir -p "$out"
cargo build --release --locked -p vbrain-ui >&2
bin=target/release/vbrain
args=(video organs/brain --turntable 360 --seconds 8 --fps 30 --size 1280x720)
alone=$("$bin" "${args[@]}" --out "$out/turn.mp4" --render-only | sed -n 's/.*"render_s": \([0-9.]*\).*/\1/p')
for f in gif mp4; do
    total=$("$bin" "${args[@]}" --out "$out/turn.$f" --force --json | sed -n 's/.*"total_s": \([0-9.]*\).*/\1/p')
    echo "$f: rendering alone ${alone} s, rendering and encoding ${total} s, ratio $(python3 -c "print(round($total / $alone, 3))")"
done
