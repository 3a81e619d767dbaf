#!/usr/bin/env bash
# Builds vbrain's packages into target/package/:
#   vbrain_VERSION-1_amd64.deb            (cargo deb; [package.metadata.deb] in ui/Cargo.toml)
#   vbrain-VERSION-x86_64-linux.tar.gz     (bin/vbrain, share/..., README, licences; runs from anywhere)
#   vbrain-VERSION-x86_64-windows.zip      (vbrain.exe, share/vbrain/, README, licences)
# Usage: scripts/package.sh [--no-windows]
# Installs what it lacks when it can (root on Debian): cargo-deb, zip, the Windows target and
# Debian's MinGW-w64 cross compiler.
set -euo pipefail
cd "$(dirname "$0")/.."

windows=1
for arg in "$@"; do
    case "$arg" in
        --no-windows) windows=0 ;;
        *) echo "usage: scripts/package.sh [--no-windows]" >&2; exit 2 ;;
    esac
done

apt_install() {
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null
    else
        echo "error: install $* first" >&2
        exit 1
    fi
}

version=$(sed -n 's/^version = "\(.*\)"/\1/p' ui/Cargo.toml | head -n 1)
out=target/package
gen=packaging/generated
rm -rf "$out" "$gen"
mkdir -p "$gen/man" "$gen/completions"

command -v cargo-deb >/dev/null || cargo install cargo-deb --locked --version 3.8.0
command -v zip >/dev/null || apt_install zip

# The binary, with no path of this checkout in it (tests check with `strings`).
cargo build --release --locked -p vbrain-ui
bin=target/release/vbrain

# Manual pages and completions, generated from the clap definitions.
"$bin" manual --out "$gen/man" >/dev/null
gzip -9n "$gen"/man/*.1
"$bin" completions bash >"$gen/completions/vbrain"
"$bin" completions zsh >"$gen/completions/_vbrain"
"$bin" completions fish >"$gen/completions/vbrain.fish"

# The Debian package.
cargo deb -p vbrain-ui --no-build --locked --output "$out/" >/dev/null
echo "wrote $(ls "$out"/*.deb)"

# A portable tree: the same files as the package, under one folder. `lay_out DIR` fills DIR/share.
lay_out() {
    local root=$1
    mkdir -p "$root/share/vbrain" "$root/share/applications" "$root/share/mime/packages" \
        "$root/share/metainfo" "$root/share/man/man1" "$root/share/icons/hicolor/scalable/apps"
    cp -r organs/brain "$root/share/vbrain/brain"
    cp packaging/io.github.vbrain.vbrain.desktop "$root/share/applications/"
    cp packaging/vbrain-mime.xml "$root/share/mime/packages/vbrain.xml"
    cp packaging/io.github.vbrain.vbrain.metainfo.xml "$root/share/metainfo/"
    cp "$gen"/man/*.1.gz "$root/share/man/man1/"
    cp packaging/icons/vbrain.svg "$root/share/icons/hicolor/scalable/apps/"
    for png in packaging/icons/vbrain-*.png; do
        size=${png##*-}
        size=${size%.png}
        mkdir -p "$root/share/icons/hicolor/${size}x${size}/apps"
        cp "$png" "$root/share/icons/hicolor/${size}x${size}/apps/vbrain.png"
    done
    cp README.md LICENSE-MIT LICENSE-APACHE "$root/"
    cp web/vendor/three/LICENSE "$root/LICENSE-three.js"
}

name=vbrain-$version-x86_64-linux
stage=$out/$name
lay_out "$stage"
mkdir -p "$stage/bin"
cp "$bin" "$stage/bin/"
tar -C "$out" -czf "$out/$name.tar.gz" "$name"
rm -rf "$stage"
echo "wrote $out/$name.tar.gz"

[ "$windows" = 1 ] || exit 0

# Windows, cross-built with MinGW-w64; the C++ runtime is linked statically (.cargo/config.toml).
target=x86_64-pc-windows-gnu
rustup target list --installed | grep -qx "$target" || rustup target add "$target"
command -v x86_64-w64-mingw32-g++ >/dev/null || apt_install g++-mingw-w64-x86-64
cargo build --release --locked -p vbrain-ui --target "$target"
name=vbrain-$version-x86_64-windows
stage=$out/$name
mkdir -p "$stage/share/vbrain"
cp -r organs/brain "$stage/share/vbrain/brain"
cp "target/$target/release/vbrain.exe" "$stage/"
x86_64-w64-mingw32-strip "$stage/vbrain.exe"
cp README.md LICENSE-MIT LICENSE-APACHE "$stage/"
cp web/vendor/three/LICENSE "$stage/LICENSE-three.js"
(cd "$out" && zip -qr "$name.zip" "$name")
rm -rf "$stage"
echo "wrote $out/$name.zip"
