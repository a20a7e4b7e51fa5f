#!/usr/bin/env bash
# Builds Rhubarb Lip Sync 1.14.0 (MIT), the lip-sync bench's public peer, from the source kept in
# third_party/rhubarb-1.14.0 (what its own build compiles, nothing fetched), into .bench/rhubarb/, and
# lays out beside it the speech models it reads (res/sphinx), taken from Debian's pocketsphinx-en-us.
# Offline: cmake, a C++17 compiler, Boost's headers and the models come from Debian's packages. About two
# minutes on two cores; a second run with the same source is a no-op. Prints the binary's path.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
src=$here/third_party/rhubarb-1.14.0
out=$here/.bench/rhubarb
stamp=$out/.source
models=/usr/share/pocketsphinx/model/en-us
want=$(cd "$src" && find . -type f -print0 | sort -z | xargs -0 sha256sum | sha256sum | cut -d' ' -f1)
if [ -x "$out/rhubarb" ] && [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ] && [ -d "$out/res/sphinx" ]; then
    echo "$out/rhubarb"
    exit 0
fi
missing=()
command -v cmake >/dev/null 2>&1 || missing+=(cmake)
command -v g++ >/dev/null 2>&1 || missing+=(g++)
[ -f /usr/include/boost/version.hpp ] || missing+=(libboost-dev)
[ -f "$models/en-us.lm.bin" ] || missing+=(pocketsphinx-en-us)
if [ ${#missing[@]} -gt 0 ]; then
    echo "toonface: installing ${missing[*]} to build Rhubarb for the lip-sync bench" >&2
    SUDO=""
    if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
    export DEBIAN_FRONTEND=noninteractive
    $SUDO apt-get update -qq
    $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "toonface: building Rhubarb 1.14.0 (about two minutes)" >&2
cmake -S "$src" -B "$work" -DCMAKE_BUILD_TYPE=Release >"$work.log" 2>&1 \
    || { cat "$work.log" >&2; echo "toonface: Rhubarb's cmake failed (log above)" >&2; exit 1; }
cmake --build "$work" --target rhubarb -j "$(nproc)" >>"$work.log" 2>&1 \
    || { tail -40 "$work.log" >&2; echo "toonface: Rhubarb's build failed (log above)" >&2; exit 1; }
rm -f "$work.log"
# Rhubarb finds its models in res/sphinx beside its binary: the acoustic model, dictionary and language
# models of Debian's pocketsphinx-en-us (the acoustic model is the one Rhubarb's own pocketsphinx
# folder carries; the release's larger continuous one is not in the public snapshot).
rm -rf "$out.part"
mkdir -p "$out.part/res/sphinx"
cp "$work/rhubarb/rhubarb" "$out.part/rhubarb"
ln -s "$models/en-us" "$out.part/res/sphinx/acoustic-model"
for f in cmudict-en-us.dict en-us-phone.lm.bin en-us.lm.bin; do ln -s "$models/$f" "$out.part/res/sphinx/$f"; done
echo "$want" >"$out.part/.source"
rm -rf "$out"
mv "$out.part" "$out"
echo "$out/rhubarb"
