#!/usr/bin/env bash
# Installs what odec needs (Debian packages only) and builds it, incrementally.
# Sourced by ./odec and ./run-tests; `odec_setup TARGET...` builds those targets.
set -euo pipefail

ODEC_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ODEC_BUILD="${ODEC_BUILD:-$ODEC_ROOT/build}"
ODEC_PACKAGES=(g++ cmake ninja-build pkg-config libeigen3-dev libreadline-dev libvtk9-dev libosmesa6-dev
               libegl-dev libgtest-dev)

odec_install_packages() {
    local missing=()
    for p in "${ODEC_PACKAGES[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    if [ ${#missing[@]} -gt 0 ]; then
        echo "odec: installing ${missing[*]}" >&2
        local sudo=""
        [ "$(id -u)" -eq 0 ] || sudo="sudo"
        $sudo apt-get update -qq >&2
        DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >&2
    fi
}

odec_setup() {
    odec_install_packages
    if [ ! -f "$ODEC_BUILD/build.ninja" ]; then
        echo "odec: configuring in $ODEC_BUILD" >&2
        cmake -S "$ODEC_ROOT" -B "$ODEC_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release >&2
    fi
    # Incremental: a second run rebuilds only what changed.
    local out
    if ! out=$(cmake --build "$ODEC_BUILD" --target "$@" -- -j"$(nproc)" 2>&1); then
        echo "$out" >&2
        echo "odec: build failed" >&2
        return 1
    fi
    if ! grep -q "no work to do" <<<"$out"; then echo "odec: built $*" >&2; fi
}
