#!/usr/bin/env bash
# Fuzzing campaign: tools/fuzz.sh [SECONDS] [TARGET...]
#
# Builds the libFuzzer targets of tests/fuzz/ in build-fuzz/ (clang, AddressSanitizer and
# UBSan; installs clang through tools/setup.sh), seeds their corpora and runs each target for
# SECONDS (default 60) in turn: `interpreter` (scripts, typed or made by the script
# generator from inputs that start with the byte 0x01) and `restore` (save files), both by
# default. Corpora grow in build-fuzz/corpus/TARGET/; an input that crashes, trips a sanitizer
# or runs over 20 s (times ODEC_TEST_TIME_SCALE: tools/setup.sh) is written to
# build-fuzz/crashes/TARGET/ and the script fails. Put such an
# input, once fixed, into tests/fuzz/regressions/TARGET/: CTest replays that directory.
# FUZZ_JOBS=N runs N processes per target (libFuzzer's -fork). Extra libFuzzer flags: FUZZ_FLAGS.
set -euo pipefail
# shellcheck source-path=SCRIPTDIR
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"

seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(interpreter restore)

odec_fuzz_setup fuzz_interpreter fuzz_restore odec
fuzz="$ODEC_FUZZ_BUILD"
src="$ODEC_ROOT/tests/fuzz"

# Seeds: the example scripts, the test scripts and the regression inputs; for restore,
# save files made by `save` from some of those scripts.
mkdir -p "$fuzz/seeds/interpreter" "$fuzz/seeds/restore"
n=0
while IFS= read -r -d '' f; do
    n=$((n + 1))
    cp "$f" "$fuzz/seeds/interpreter/$(printf '%03d' $n)-$(basename "$f")"
done < <(find "$ODEC_ROOT/examples" "$ODEC_ROOT/tests/scripts" -name '*.dat' -print0 | sort -z)
# Inputs for the script generator (tests/fuzz/script_gen.h): the marker byte 0x01, then
# choices. Pseudo-random bytes from a fixed seed, so every campaign starts from the same ones.
for s in $(seq 1 24); do
    f="$fuzz/seeds/interpreter/gen-$(printf '%02d' "$s")"
    [ -f "$f" ] && continue
    RANDOM=$s
    bytes='\001'
    for _ in $(seq 1 $((40 + 40 * s))); do
        v=$((RANDOM % 256)) # not inside $(...): a subshell draws from a new seed
        bytes+="\\0$(printf '%03o' "$v")"
    done
    printf '%b' "$bytes" > "$f"
done
if [ ! -f "$fuzz/seeds/restore/empty.sav" ]; then
    (
        cd "$fuzz/seeds/restore"
        "$fuzz/odec" --quiet -c "save 'empty'"
        "$fuzz/odec" --quiet -c "poly brick 0 1 0 1 0 1
prop mat=1 dens=2000
grav 0 0 -10
hist zdis 0.5,0.5,1
set dt 1e-3
step 10
save 'brick'" >/dev/null
        for f in "$ODEC_ROOT"/examples/*/*.dat; do
            name="$(basename "$f" .dat)"
            # The example's own commands, cut short, then a save.
            { head -n 60 "$f" | sed -e 's/^\( *\)\(step\|solve\|plot\|export\|call\) .*/\1; &/I'
              printf "\nstep 20\nsave '%s'\n" "$name"; } > "/tmp/odec-seed-$$.dat"
            "$fuzz/odec" --quiet "/tmp/odec-seed-$$.dat" >/dev/null 2>&1 || true
            rm -f "/tmp/odec-seed-$$.dat"
        done
    )
fi

# A deformable block, so that mutations reach the zone, gridpoint and loaded-face sections
# (made apart from the seeds above, which an older campaign directory already holds).
if [ ! -f "$fuzz/seeds/restore/zoned.sav" ]; then
    (
        cd "$fuzz/seeds/restore"
        "$fuzz/odec" --quiet -c "poly brick 0 1 0 1 0 1
prop mat=1 dens=2500 ymod=10e9 prat=0.25 coh=3e5 fric=30 ten=1e5
change cons=2
gen edge 0.5
grav 0 0 -10
bound zvel 0 range z -0.001 0.001
bound stress 0 0 -1e6 0 0 0 range z 0.999 1.001
hist zdis 0.5 0.5 1
hist szz 0.5 0.5 0.5
hist zreaction range z -0.001 0.001
step 10
save 'zoned'" >/dev/null 2>&1 || true
    )
fi

# 20 s: the costliest inputs a bounded session allows (a `whilestepping` function that cuts the
# blocks with a joint set at every step, so that every step detects the contacts anew) take up to
# 23 s with the sanitizers and coverage on a busy two-core machine; a hang takes for ever.
input_limit=$(odec_time_limit 20)
status=0
for t in "${targets[@]}"; do
    mkdir -p "$fuzz/corpus/$t" "$fuzz/crashes/$t"
    dict=()
    [ "$t" = interpreter ] && dict=(-dict="$src/odec.dict")
    max_len=4096
    [ "$t" = restore ] && max_len=65536
    fork=()
    [ "${FUZZ_JOBS:-1}" -gt 1 ] && fork=(-fork="$FUZZ_JOBS" -ignore_crashes=0)
    echo "fuzz: $t for $seconds s" >&2
    # shellcheck disable=SC2086
    if ! (cd "$fuzz" && "./fuzz_$t" "$fuzz/corpus/$t" "$fuzz/seeds/$t" "$src/regressions/$t" \
            -max_total_time="$seconds" -timeout="$input_limit" -rss_limit_mb=2560 -max_len=$max_len \
            -artifact_prefix="$fuzz/crashes/$t/" -print_final_stats=1 "${dict[@]}" "${fork[@]}" \
            ${FUZZ_FLAGS:-} 2>&1 | tee "$fuzz/fuzz-$t.log" | grep -E '^(#[0-9]+ *(INITED|DONE)|==[0-9]+==ERROR|SUMMARY|stat::|Done )' >&2;
            exit "${PIPESTATUS[0]}"); then
        echo "fuzz: $t FAILED: see $fuzz/fuzz-$t.log and $fuzz/crashes/$t/" >&2
        status=1
    fi
done
exit $status
