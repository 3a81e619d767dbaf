#!/usr/bin/env bash
# Renders a fixed list of views, modes and layouts of the default brain and prints one SHA-256 per
# PNG. A refactoring that must not change behaviour gives the same list before and after:
#   scripts/render-hashes.sh target/release/vbrain > before.txt   (then after, and diff)
set -euo pipefail
cd "$(dirname "$0")/.."
VBRAIN="${1:-target/release/vbrain}"
OUT="$(mktemp -d)"
trap 'rm -rf "$OUT"' EXIT
S=(organs/brain --size 256x256)
i=0
r() {
    i=$((i + 1))
    local f="$OUT/$i.png"
    "$VBRAIN" render "${S[@]}" --out "$f" "$@" >/dev/null
    printf '%02d %s  %s\n' "$i" "$(sha256sum "$f" | cut -c1-16)" "$*"
}
r --view anterior
r --orbit 30,15
r --view left
r --view superior
r --view inferior --cull none
r --orbit -60,20 --cull frustum
r --orbit 30,15 --show skull
r --orbit 30,15 --show skull --debug-culled
r --orbit 120,-10 --debug-culled
r --orbit -90,5 --opacity "Left hemisphere/Frontal lobe=0.35"
r --orbit 45,30 --opacity all=0.5
r --orbit -90,5 --opacity "Left hemisphere/Frontal lobe=0.35" "Left hemisphere/Parietal lobe=0.5" --transparency screendoor-whitenoise
r --orbit -90,5 --opacity "Left hemisphere/Frontal lobe=0.35" "Left hemisphere/Parietal lobe=0.5" --transparency screendoor-pixeltree
r --orbit -90,5 --opacity "Left hemisphere/Frontal lobe=0.35" "Left hemisphere/Parietal lobe=0.5" --transparency alpha-unsorted
r --orbit -90,5 --opacity "Left hemisphere/Frontal lobe=0.35" "Left hemisphere/Parietal lobe=0.5" --transparency alpha-sorted
r --orbit -90,5 --opacity "Left hemisphere/Frontal lobe=0.35" "Left hemisphere/Parietal lobe=0.5" --transparency weighted-blended
r --orbit -90,5 --opacity "Left hemisphere/Frontal lobe=0.35" "Left hemisphere/Parietal lobe=0.5" --transparency exact
r --orbit 10,10 --opacity all=0.4 --subsamples 16 --region 32 --k 2
r --orbit 10,10 --opacity all=0.4 --draw-order-seed 7
r --view right --transparent
r --route orbit:40 --hide "Right hemisphere/Frontal lobe" "Right hemisphere/Parietal lobe"
r --orbit 200,40 --show scalp skull --opacity scalp=0.3 skull=0.6 --cull occlusion
r --orbit 30,15 --clip coronal=-10
r --orbit -40,20 --clip axial=20 --clip sagittal=5:flip --whole thalamus_l,caudate_l
r --orbit 30,15 --clip coronal=-10 --caps off --opacity "Left hemisphere=0.5"
r --orbit 30,15 --clip 0.3,0.2,0.93,15 --cull occlusion --debug-culled
r --orbit 30,15 --highlight hippocampus_l amygdala_l --opacity "Left hemisphere=0.4"
r --view left --labels all
r --orbit 30,15 --labels thalamus_l,precentral_l --clip coronal=-15
r --orbit 30,15 --clip coronal=-10 --transparency peel --opacity all=0.5
r --orbit 30,15 --clip coronal=-10 --transparency dual-peel --opacity all=0.5
r --orbit 30,15 --transparency kbuffer --opacity all=0.5
