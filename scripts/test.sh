#!/usr/bin/env bash
# vbrain's test command (README.md): formatting, lints, the whole test suite, and the packages.
# GPU tests need a Vulkan (or other wgpu) adapter; on a machine with none, this installs Mesa's
# software Vulkan driver (lavapipe) when it can (root on Debian/Ubuntu), else says what to install.
set -euo pipefail
cd "$(dirname "$0")/.."

have_vulkan_driver() {
    compgen -G "/usr/share/vulkan/icd.d/*.json" >/dev/null || compgen -G "/etc/vulkan/icd.d/*.json" >/dev/null
}

if ! have_vulkan_driver; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "No Vulkan driver found: installing Mesa's software Vulkan (mesa-vulkan-drivers)"
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq mesa-vulkan-drivers >/dev/null
    else
        echo "warning: no Vulkan driver found; GPU tests will fail. Install one, e.g. 'sudo apt-get install mesa-vulkan-drivers'" >&2
    fi
fi
# The export tests run the Khronos glTF validator (npm package gltf-validator) under Node.js.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "No Node.js found: installing Debian's nodejs and npm"
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq nodejs npm >/dev/null
    else
        echo "warning: no Node.js found; the glTF validator tests will fail. Install nodejs and npm" >&2
    fi
fi
# The web page tests open exported pages in Debian's Chromium, driven by playwright-core.
if [ ! -x /usr/bin/chromium ] && [ -z "${CHROMIUM:-}" ]; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "No Chromium found: installing Debian's chromium"
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
    else
        echo "warning: no Chromium found; the web page tests will fail. Install chromium (or set CHROMIUM)" >&2
    fi
fi
if ! command -v ffprobe >/dev/null || ! command -v pdftotext >/dev/null; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "No ffmpeg or Poppler found: installing Debian's ffmpeg and poppler-utils"
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq ffmpeg poppler-utils >/dev/null
    else
        echo "warning: no ffmpeg or Poppler found; the video and PDF tests will fail. Install ffmpeg and poppler-utils" >&2
    fi
fi
if command -v npm >/dev/null && { [ ! -d scripts/web/node_modules/gltf-validator ] || [ ! -d scripts/web/node_modules/playwright-core ]; }; then
    npm ci --prefix scripts/web --no-audit --no-fund --silent
fi
# The Anki deck tests import decks with Anki's own collection library (PyPI package anki).
if ! python3 -c "import anki" 2>/dev/null; then
    echo "No Anki library found: installing the anki package from PyPI"
    python3 -m pip install --quiet anki==26.9.3 || echo "warning: could not install anki; the deck tests will fail" >&2
fi
# The Vulkan loader complains without a runtime dir; give it a private one.
if [ -z "${XDG_RUNTIME_DIR:-}" ] || [ ! -d "${XDG_RUNTIME_DIR}" ]; then
    XDG_RUNTIME_DIR="$(mktemp -d)"
    export XDG_RUNTIME_DIR
fi

cargo fmt --all --check
cargo clippy --workspace --all-targets --locked -- -D warnings
# In the release profile: the packages below reuse this build instead of compiling it all again.
cargo test --workspace --locked --release
# The packages, built and tested as a user installs them (the .deb, the archive, the Windows zip).
scripts/package.sh
scripts/test-packages.sh
