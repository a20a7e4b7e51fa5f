#!/usr/bin/env bash
# Installs Mesa's EGL/OpenGL (software rasteriser llvmpipe included) and Cairo with apt-get, only
# when the libraries are missing. moderngl's offscreen context needs libEGL plus a Mesa driver;
# the CPU renderer (cairocffi) needs libcairo2.
set -euo pipefail

have_lib() { ldconfig -p 2>/dev/null | grep -q "$1"; }
have_dri() {
    # llvmpipe lives in swrast_dri.so (Mesa < 24) or libgallium-*.so (Mesa >= 24).
    compgen -G '/usr/lib/*/dri/swrast_dri.so' >/dev/null || compgen -G '/usr/lib/*/libgallium*.so' >/dev/null \
        || compgen -G '/usr/lib/dri/swrast_dri.so' >/dev/null
}

if have_lib 'libEGL.so.1' && have_lib 'libEGL_mesa.so.0' && have_lib 'libgbm.so.1' && have_dri && have_lib 'libcairo.so.2'; then
    exit 0
fi

echo "toonface: installing Mesa EGL/OpenGL and Cairo system packages (libegl1 libegl-mesa0 libgl1-mesa-dri libgbm1 libcairo2)" >&2
if ! command -v apt-get >/dev/null 2>&1; then
    echo "toonface: Mesa's EGL or Cairo is missing and apt-get is not available; install libEGL + Mesa and libcairo2 by hand" >&2
    exit 1
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends libegl1 libegl-mesa0 libgl1-mesa-dri libgbm1 libcairo2 >/dev/null
