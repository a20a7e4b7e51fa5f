#!/usr/bin/env bash
# Installs Debian's Chromium and its chromedriver with apt-get, and the npm packages of package.json,
# only when missing, for the browser tests (browser builds cannot be downloaded here; Selenium is pointed at these). Never
# fails the build: where they cannot be installed, the browser tests skip and say why.
set -uo pipefail

# The npm packages of package.json (lottie-web and axe-core for browser tests; @mediapipe/tasks-vision,
# which the room server serves to its performer page, and @noble/ciphers and @noble/hashes, to its viewer
# page for sealed streams), from the lockfile, only when missing; without
# npm, the tests that need them skip and the performer page says what is missing.
if [ ! -f node_modules/lottie-web/build/player/lottie.min.js ] || [ ! -f node_modules/axe-core/axe.min.js ] \
        || [ ! -f node_modules/@mediapipe/tasks-vision/vision_bundle.mjs ] \
        || [ ! -f node_modules/@noble/ciphers/aes.js ] || [ ! -f node_modules/@noble/hashes/hkdf.js ]; then
    if command -v npm >/dev/null 2>&1; then
        npm ci --no-audit --no-fund --silent >/dev/null 2>&1 || echo "toonface: npm ci failed: the Lottie, accessibility and performer-page browser tests will skip" >&2
    else
        echo "toonface: npm is missing: the Lottie and performer-page browser tests will skip" >&2
    fi
fi

if command -v chromium >/dev/null 2>&1 && command -v chromedriver >/dev/null 2>&1; then
    exit 0
fi
if ! command -v apt-get >/dev/null 2>&1; then
    echo "toonface: chromium and chromedriver are missing and apt-get is not available: the browser tests will skip" >&2
    exit 0
fi
echo "toonface: installing chromium and chromium-driver for the studio's browser tests" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
if ! { $SUDO apt-get update -qq && $SUDO apt-get install -y -qq --no-install-recommends chromium chromium-driver >/dev/null; }; then
    echo "toonface: could not install chromium: the browser tests will skip" >&2
fi
exit 0
