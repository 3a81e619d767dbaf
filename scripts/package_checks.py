#!/usr/bin/env python3
"""Checks of the files scripts/test-packages.sh finds in vbrain's packages (standard library and
ImageMagick's `convert` only):

  brain PNG [--viewer]   the picture shows the brain: enough tissue-coloured pixels (saturated,
                         not dark) in its middle (a whole render), or in the viewport of a
                         screenshot of the viewer window (--viewer)
  mime XML DESKTOP       the shared-mime-info file maps *.vbscene and *.vblesson to the types
                         the launcher opens
  glb FILE               a binary glTF 2.0 file with a JSON chunk naming meshes

Exits 0 when the check holds, 1 (saying why) when not."""
import colorsys
import json
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET


def pixels(path, width, height):
    """The picture scaled to width x height, as (r, g, b) tuples in 0..1, row by row."""
    ppm = subprocess.run(
        ["convert", path, "-background", "black", "-alpha", "remove", "-resize", f"{width}x{height}!",
         "-depth", "8", "ppm:-"],
        check=True, capture_output=True).stdout
    # P6 header: magic, width, height, max, one whitespace byte each.
    fields, rest = ppm.split(maxsplit=4)[:4], ppm.split(maxsplit=4)[4]
    assert fields[0] == b"P6", "not a binary PPM"
    data = rest[: width * height * 3]
    return [tuple(c / 255 for c in data[i:i + 3]) for i in range(0, len(data), 3)]


def tissue_share(path, viewer):
    w, h = 128, 80 if viewer else 128
    px = pixels(path, w, h)
    # The viewer's viewport lies right of the organ panel and between the bars; a render is all view.
    x0, x1, y0, y1 = (int(w * 0.3), int(w * 0.95), int(h * 0.1), int(h * 0.9)) if viewer else (0, w, 0, h)
    region = [px[y * w + x] for y in range(y0, y1) for x in range(x0, x1)]
    tissue = [p for p in region if colorsys.rgb_to_hsv(*p)[1] > 0.2 and colorsys.rgb_to_hsv(*p)[2] > 0.25]
    return len(tissue) / len(region)


def brain(args):
    share = tissue_share(args[0], "--viewer" in args)
    need = 0.1
    print(f"{args[0]}: {share:.0%} of the view is tissue-coloured (need {need:.0%})")
    return share >= need


def mime(args):
    ns = {"m": "http://www.freedesktop.org/standards/shared-mime-info"}
    types = {g.get("pattern"): t.get("type") for t in ET.parse(args[0]).getroot().findall("m:mime-type", ns)
             for g in t.findall("m:glob", ns)}
    desktop = open(args[1], encoding="utf-8").read()
    opened = next(l.split("=", 1)[1] for l in desktop.splitlines() if l.startswith("MimeType=")).split(";")
    ok = True
    for pattern in ("*.vbscene", "*.vblesson"):
        if pattern not in types:
            print(f"{args[0]}: no type for {pattern}")
            ok = False
        elif types[pattern] not in opened:
            print(f"{args[1]}: does not open {types[pattern]} ({pattern})")
            ok = False
    return ok


def glb(args):
    data = open(args[0], "rb").read()
    magic, version, length = struct.unpack_from("<4sII", data)
    chunk_length, chunk_type = struct.unpack_from("<II", data, 12)
    if magic != b"glTF" or version != 2 or length != len(data) or chunk_type != 0x4E4F534A:
        print(f"{args[0]}: not a binary glTF 2.0 file")
        return False
    meshes = json.loads(data[20:20 + chunk_length]).get("meshes", [])
    print(f"{args[0]}: {len(meshes)} meshes, {len(data) / 1e6:.1f} MB")
    return len(meshes) > 50


if __name__ == "__main__":
    checks = {"brain": brain, "mime": mime, "glb": glb}
    if len(sys.argv) < 3 or sys.argv[1] not in checks:
        sys.exit(__doc__)
    sys.exit(0 if checks[sys.argv[1]](sys.argv[2:]) else 1)
