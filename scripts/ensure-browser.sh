#!/usr/bin/env bash
# Installs Debian's Chromium and its chromedriver with apt-get, only when missing, for the studio's
# browser tests (browser builds cannot be downloaded here; Selenium is pointed at these). Never
# fails the build: where they cannot be installed, the browser tests skip and say why.
set -uo pipefail

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
