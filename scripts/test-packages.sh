#!/usr/bin/env bash
# Tests the packages that scripts/package.sh wrote into target/package/, as a user installs them:
#   - the .deb, extracted with dpkg-deb -x into a temporary root, and the Linux archive, unpacked
#     into a temporary folder: each binary run from / with an empty HOME, no XDG variables and
#     this checkout hidden (a mount namespace with a tmpfs over it): `info` finds the default
#     brain (all its organs) there, `render` draws it, `lesson render cortex` finds the lesson by
#     name; the viewer, started under Xvfb, shows the brain (a screenshot, checked for it);
#   - the Windows zip under Wine: --version, info (all the organs), export --gltf, and render (Wine's
#     Vulkan over the host's) byte-identical to the Linux binary's;
#   - the packaged launcher, metainfo and MIME types: desktop-file-validate, appstreamcli;
#   - the release binary holds no path of this checkout;
#   - `vbrain render` with XDG_RUNTIME_DIR unset prints nothing to stderr.
# Usage: scripts/test-packages.sh [--no-windows]. Prints "N passed, N failed" last.
set -uo pipefail
cd "$(dirname "$0")/.."
checkout=$(pwd)
windows=1
[ "${1:-}" = --no-windows ] && windows=0

passed=0
failed=0
check() { # check NAME COMMAND...: runs COMMAND, counts and reports it
    local name=$1
    shift
    if "$@"; then
        echo "ok: $name"
        passed=$((passed + 1))
    else
        echo "FAILED: $name"
        failed=$((failed + 1))
    fi
}

apt_need() { # apt_need COMMAND PACKAGE: installs PACKAGE where COMMAND is missing
    command -v "$1" >/dev/null && return
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$2" >/dev/null
    else
        echo "warning: $1 is missing; install $2" >&2
    fi
}
apt_need desktop-file-validate desktop-file-utils
apt_need appstreamcli appstream
apt_need xvfb-run xvfb
apt_need import imagemagick
apt_need xdotool xdotool
apt_need strings binutils
[ "$windows" = 1 ] && apt_need wine wine64

version=$(sed -n 's/^version = "\(.*\)"/\1/p' ui/Cargo.toml | head -n 1)
pkg=$checkout/target/package
work=$(mktemp -d /tmp/vbrain-packages.XXXXXX)
trap 'rm -rf "$work"' EXIT

# hidden CMD...: runs CMD from / with an empty HOME, no XDG or vbrain variables, and this
# checkout (and the cargo home) hidden under empty tmpfs mounts.
hidden() {
    local home
    home=$(mktemp -d "$work/home.XXXXXX")
    unshare --mount --propagation private -- env -i PATH=/usr/bin:/bin HOME="$home" \
        ${DISPLAY:+DISPLAY=$DISPLAY} CHECKOUT="$checkout" CARGO_HOME="${CARGO_HOME:-$HOME/.cargo}" \
        bash -c 'mount -t tmpfs none "$CHECKOUT" && mount -t tmpfs none "$CARGO_HOME" 2>/dev/null; cd / && exec "$@"' hidden "$@"
}

organs_of() { # organs_of JSON: the number of organs `vbrain info --json` printed
    python3 -c 'import json, sys; print(len(json.load(sys.stdin)["organs"]))' <"$1"
}
# The default brain's organs, as its manifest lists them.
ORGANS="$(organs_of organs/brain/organset.json)"

# test_install NAME BIN: the tests of one installed tree whose binary is BIN.
test_install() {
    local name=$1 bin=$2 out=$work/$1
    mkdir -p "$out"
    check "$name: the checkout is hidden from its commands" \
        hidden bash -c "[ ! -e '$checkout/Cargo.toml' ] && [ ! -e '$checkout/organs' ]"
    hidden "$bin" info --json >"$out/info.json" 2>"$out/info.err"
    check "$name: info finds the default brain, $ORGANS organs" test "$(organs_of "$out/info.json" 2>/dev/null)" = "$ORGANS"
    check "$name: info opened the brain inside the install" \
        grep -q "\"path\": \"$(dirname "$(dirname "$bin")")/share/vbrain/brain\"" "$out/info.json"
    hidden "$bin" render --out "$out/brain.png" --size 256x256 >"$out/render.out" 2>"$out/render.err"
    check "$name: render draws the brain" python3 scripts/package_checks.py brain "$out/brain.png"
    hidden "$bin" lesson render cortex --out "$out/lesson" --size 256x192 >"$out/lesson.out" 2>&1
    check "$name: lesson render finds the cortex lesson by name" test -s "$out/lesson/01.png" -a -s "$out/lesson/lesson.md"
    if [ "$failed" != 0 ]; then
        cat "$out"/*.err "$out/lesson.out" 2>/dev/null | head -20
    fi
}

# The Debian package.
deb=$(ls "$pkg"/vbrain_"$version"*_amd64.deb)
root=$work/deb-root
dpkg-deb -x "$deb" "$root"
test_install deb "$root/usr/bin/vbrain"
check "deb: the launcher passes desktop-file-validate" \
    desktop-file-validate "$root/usr/share/applications/io.github.vbrain.vbrain.desktop"
check "deb: the metainfo passes appstreamcli validate" \
    appstreamcli validate --no-net "$root/usr/share/metainfo/io.github.vbrain.vbrain.metainfo.xml"
check "deb: the MIME types map .vbscene and .vblesson" \
    python3 scripts/package_checks.py mime "$root/usr/share/mime/packages/vbrain.xml" \
    "$root/usr/share/applications/io.github.vbrain.vbrain.desktop"
check "deb: icons (SVG and PNG sizes), manual page and completions" bash -c "
    test -s '$root/usr/share/icons/hicolor/scalable/apps/vbrain.svg' &&
    test -s '$root/usr/share/icons/hicolor/256x256/apps/vbrain.png' &&
    zcat '$root/usr/share/man/man1/vbrain.1.gz' | grep -q 'vbrain' &&
    zcat '$root/usr/share/man/man1/vbrain-render.1.gz' | grep -q -- 'clip' &&
    grep -q 'vbrain' '$root/usr/share/bash-completion/completions/vbrain' &&
    grep -q 'vbrain' '$root/usr/share/zsh/vendor-completions/_vbrain' &&
    grep -q 'vbrain' '$root/usr/share/fish/vendor_completions.d/vbrain.fish'"
check "deb: --version names the version and the commit" \
    bash -c "'$root/usr/bin/vbrain' --version | grep -Eq '^vbrain $version \\(commit [0-9a-f]{7,}\\)'"
check "the release binary holds no path of the checkout" \
    bash -c "! strings '$checkout/target/release/vbrain' | grep -qF '$checkout'"
env -u XDG_RUNTIME_DIR "$checkout/target/release/vbrain" render --out "$work/quiet.png" --size 64x64 \
    >"$work/quiet.out" 2>"$work/quiet.err"
check "render with XDG_RUNTIME_DIR unset prints nothing to stderr" test ! -s "$work/quiet.err"
[ -s "$work/quiet.err" ] && head -5 "$work/quiet.err"

# The viewer, from the package, under Xvfb: the window shows the brain.
viewer_shot() {
    local bin=$1 shot=$2
    hidden bash -c "
        Xvfb :57 -screen 0 1280x800x24 >/dev/null 2>&1 & xvfb=\$!
        sleep 2
        export DISPLAY=:57
        '$bin' >/dev/null 2>&1 & viewer=\$!
        for i in \$(seq 1 60); do
            sleep 2
            if xdotool search --name 'vbrain - ' >/dev/null 2>&1; then sleep 8; break; fi
        done
        import -window root '$shot' 2>/dev/null
        kill \$viewer \$xvfb 2>/dev/null; wait 2>/dev/null; true"
}
viewer_shot "$root/usr/bin/vbrain" "$work/viewer.png"
check "deb: the viewer shows the brain under Xvfb" python3 scripts/package_checks.py brain "$work/viewer.png" --viewer
[ -n "${VBRAIN_KEEP_SCREENSHOT:-}" ] && cp "$work/viewer.png" "$VBRAIN_KEEP_SCREENSHOT"

# The portable archive.
tar -C "$work" -xzf "$pkg/vbrain-$version-x86_64-linux.tar.gz"
test_install archive "$work/vbrain-$version-x86_64-linux/bin/vbrain"

# The Windows zip, under Wine.
if [ "$windows" = 1 ]; then
    unzip -q "$pkg/vbrain-$version-x86_64-windows.zip" -d "$work"
    win=$work/vbrain-$version-x86_64-windows
    # Rust's std needs ProcessPrng, which Debian's Wine 8 lacks: a test-only stand-in DLL.
    x86_64-w64-mingw32-gcc -O2 -shared -o "$win/bcryptprimitives.dll" scripts/wine/bcryptprimitives.c -ladvapi32
    export WINEPREFIX=$work/wine WINEDEBUG=-all WINEDLLOVERRIDES="bcryptprimitives=n"
    wineboot -i >/dev/null 2>&1
    run_wine() { (cd "$win" && timeout 300 wine ./vbrain.exe "$@"); }
    run_wine --version >"$work/win-version.out" 2>/dev/null
    check "windows: vbrain.exe --version" grep -q "^vbrain $version" "$work/win-version.out"
    run_wine info --json >"$work/win-info.json" 2>"$work/win-info.err"
    check "windows: info finds the brain beside the executable, $ORGANS organs" \
        test "$(organs_of "$work/win-info.json" 2>/dev/null)" = "$ORGANS"
    run_wine export --gltf brain.glb >"$work/win-export.out" 2>&1
    check "windows: export --gltf writes the model" python3 scripts/package_checks.py glb "$win/brain.glb"
    # Rendering: Wine's Vulkan (over this machine's, lavapipe here) needs an X display for its
    # driver; the picture is the Linux binary's, byte for byte. Wine's server, started above without
    # a display, is stopped first so that the display driver starts again with one.
    wineserver -k 2>/dev/null
    (cd "$win" && WGPU_BACKEND=vulkan timeout 300 xvfb-run -a wine ./vbrain.exe render --out win.png --size 128x128) \
        >"$work/win-render.out" 2>&1
    "$checkout/target/release/vbrain" render "$checkout/organs/brain" --out "$work/linux.png" --size 128x128 >/dev/null
    check "windows: render under Wine gives the Linux render's bytes" cmp -s "$win/win.png" "$work/linux.png"
    if [ "$failed" != 0 ]; then head -5 "$work/win-info.err" "$work/win-export.out" "$work/win-render.out"; fi
    # Wine's server outlives its programs for a while; stop it before the prefix is removed.
    wineserver -k 2>/dev/null
    wineserver -w 2>/dev/null
fi

echo "packages: $passed passed, $failed failed"
[ "$failed" = 0 ]
