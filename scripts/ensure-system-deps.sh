#!/usr/bin/env bash
# Installs Mesa's EGL/OpenGL (software rasteriser llvmpipe included), Cairo and espeak-ng with
# apt-get, only when they are missing. moderngl's offscreen context needs libEGL plus a Mesa driver;
# the CPU renderer (cairocffi) needs libcairo2; espeak-ng (GPL-3, used by the tests and the bench
# only, never linked into toonface) speaks sentences in other languages with their phoneme timings;
# nats-server (Apache-2.0) is the publish/subscribe engine room servers share rooms through (the tests
# and the bench start one on loopback).
set -euo pipefail

have_lib() { ldconfig -p 2>/dev/null | grep -q "$1"; }
have_dri() {
    # llvmpipe lives in swrast_dri.so (Mesa < 24) or libgallium-*.so (Mesa >= 24).
    compgen -G '/usr/lib/*/dri/swrast_dri.so' >/dev/null || compgen -G '/usr/lib/*/libgallium*.so' >/dev/null \
        || compgen -G '/usr/lib/dri/swrast_dri.so' >/dev/null
}

packages=()
if ! (have_lib 'libEGL.so.1' && have_lib 'libEGL_mesa.so.0' && have_lib 'libgbm.so.1' && have_dri && have_lib 'libcairo.so.2'); then
    packages+=(libegl1 libegl-mesa0 libgl1-mesa-dri libgbm1 libcairo2)
fi
if ! have_lib 'libespeak-ng.so.1'; then
    packages+=(espeak-ng)
fi
if ! command -v nats-server >/dev/null 2>&1; then
    packages+=(nats-server)
fi
if [ ${#packages[@]} -eq 0 ]; then
    exit 0
fi

echo "toonface: installing system packages: ${packages[*]}" >&2
if ! command -v apt-get >/dev/null 2>&1; then
    echo "toonface: ${packages[*]} missing and apt-get is not available; install them by hand" >&2
    exit 1
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${packages[@]}" >/dev/null
