#!/usr/bin/env bash
# Installs what odec needs (Debian packages only) and builds it, incrementally.
# Sourced by ./odec and ./run-tests; `odec_setup TARGET...` builds those targets.
# `odec_fuzz_setup TARGET...` does the same in the sanitizer and fuzzing build (build-fuzz/,
# clang), `odec_san_setup TARGET...` in the sanitizer build with gcc (build-san/).
set -euo pipefail

ODEC_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ODEC_BUILD="${ODEC_BUILD:-$ODEC_ROOT/build}"
ODEC_FUZZ_BUILD="${ODEC_FUZZ_BUILD:-$ODEC_ROOT/build-fuzz}"
ODEC_SAN_BUILD="${ODEC_SAN_BUILD:-$ODEC_ROOT/build-san}"
ODEC_PACKAGES=(g++ cmake ninja-build pkg-config libeigen3-dev libreadline-dev libvtk9-dev libosmesa6-dev
               libegl-dev libgtest-dev libgmsh-dev
               clang libclang-rt-14-dev) # clang and its libFuzzer and sanitizer runtimes: tests/fuzz/

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

# odec_build DIR "CMAKE OPTIONS" TARGET...: configure DIR once with the options, then build.
odec_build() {
    local dir="$1" options="$2"
    shift 2
    if [ ! -f "$dir/build.ninja" ]; then
        echo "odec: configuring in $dir" >&2
        # shellcheck disable=SC2086
        cmake -S "$ODEC_ROOT" -B "$dir" -G Ninja $options >&2
    fi
    # Incremental: a second run rebuilds only what changed.
    local out
    if ! out=$(cmake --build "$dir" --target "$@" -- -j"${ODEC_JOBS:-$(nproc)}" 2>&1); then
        echo "$out" >&2
        echo "odec: build failed" >&2
        return 1
    fi
    if ! grep -q "no work to do" <<<"$out"; then echo "odec: built $* in $dir" >&2; fi
}

odec_setup() {
    odec_install_packages
    odec_build "$ODEC_BUILD" "-DCMAKE_BUILD_TYPE=Release" "$@"
}

# The factor of every time limit of the tests (CTest's limits set by ./run-tests, the waits of
# the tests themselves, libFuzzer's limit of one input): ODEC_TEST_TIME_SCALE, a positive
# number, by default 1, or 3 under CI (CI set, and neither false nor 0), whose machines are
# shared and loaded. Prints it; fails on anything but a positive number.
odec_time_scale() {
    local s="${ODEC_TEST_TIME_SCALE:-}"
    if [ -z "$s" ]; then
        case "${CI:-}" in "" | false | 0) s=1 ;; *) s=3 ;; esac
    fi
    if ! [[ $s =~ ^[0-9]*\.?[0-9]+$ ]] || ! awk -v s="$s" 'BEGIN { exit !(s > 0) }'; then
        echo "odec: ODEC_TEST_TIME_SCALE must be a positive number, not '$s'" >&2
        return 1
    fi
    echo "$s"
}

# odec_time_limit SECONDS: a limit of SECONDS on an idle machine, times the scale, in whole seconds.
odec_time_limit() {
    local s
    s=$(odec_time_scale) || return 1
    awk -v b="$1" -v s="$s" 'BEGIN { t = b * s; printf "%d\n", (t == int(t)) ? t : int(t) + 1 }'
}

# Whether clang can link a libFuzzer program here.
odec_have_libfuzzer() {
    command -v clang++ >/dev/null 2>&1 &&
        echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, unsigned long) { return 0; }' |
            clang++ -fsanitize=fuzzer -x c++ - -o /dev/null >/dev/null 2>&1
}

# AddressSanitizer, UBSan and libFuzzer, clang, no pictures (see CMakeLists.txt).
odec_fuzz_setup() {
    odec_install_packages
    CC=clang CXX=clang++ odec_build "$ODEC_FUZZ_BUILD" "-DCMAKE_BUILD_TYPE=RelWithDebInfo -DODEC_FUZZ=ON" "$@"
}

# AddressSanitizer and UBSan with gcc, no pictures: where clang's libFuzzer is missing.
odec_san_setup() {
    odec_install_packages
    odec_build "$ODEC_SAN_BUILD" "-DCMAKE_BUILD_TYPE=RelWithDebInfo -DODEC_SANITIZE=ON -DODEC_PICTURES=OFF" "$@"
}
