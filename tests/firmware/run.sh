#!/usr/bin/env bash
# Runs the firmware on QEMU's mps2-an386 (Cortex-M4F) with the FPU square root and with the
# software one (feature soft-sqrt), runs the same scenario on the host, and fails unless
# every plan succeeded and the three digests equal tests/firmware/DIGEST.
# Output of the FPU run is kept in target/fw-run.txt for footprint.sh.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
cd "$here"
QEMU=(qemu-system-arm -machine mps2-an386 -nographic
      -semihosting-config enable=on,target=native
      -icount shift=0,align=off,sleep=off)
expected="$(tr -d '[:space:]' < DIGEST)"
fail() { echo "FAIL: $*" >&2; exit 1; }

run_fw() { # $1 = output file, rest = cargo args
    local out="$1"; shift
    cargo build --release "$@"
    local elf
    elf="$(cargo build --release "$@" --message-format=json 2>/dev/null \
        | sed -n 's/.*"executable":"\([^"]*\)".*/\1/p' | tail -1)"
    [ -n "$elf" ] || fail "no firmware executable"
    local rc=0
    timeout 600 "${QEMU[@]}" -kernel "$elf" > "$out" || rc=$?
    cat "$out"
    [ "$rc" -eq 0 ] || fail "firmware exited $rc ($out)"
}

digest_of() { sed -n 's/^digest=\(0x[0-9a-f]*\)$/\1/p' "$1" | tail -1; }

echo "== firmware, FPU square root (VSQRT.F32)"
run_fw target/fw-run.txt
echo "== firmware, software square root (feature soft-sqrt)"
run_fw target/fw-run-soft.txt --features soft-sqrt --target-dir target/soft
echo "== host (x86_64), same scenario"
(cd ../.. && cargo test -p integration-tests --test firmware_digest -- --nocapture) \
    > target/host-run.txt 2>&1 || { cat target/host-run.txt; fail "host test failed"; }
grep -E '^(case|digest=)' target/host-run.txt

mcu="$(digest_of target/fw-run.txt)"
soft="$(digest_of target/fw-run-soft.txt)"
host="$(digest_of target/host-run.txt)"
echo "digest: expected $expected  mcu(vsqrt) $mcu  mcu(soft-sqrt) $soft  host $host"
[ "$mcu" = "$expected" ] || fail "MCU digest $mcu != DIGEST $expected"
[ "$soft" = "$expected" ] || fail "soft-sqrt MCU digest $soft != DIGEST $expected"
[ "$host" = "$expected" ] || fail "host digest $host != DIGEST $expected"
# Per-case lines too (the host prints them without tick counts).
strip() { grep '^case .* status=' "$1" | sed -E 's/ ticks=[0-9]+ instructions=[0-9]+//'; }
diff <(strip target/fw-run.txt) <(strip target/host-run.txt) || fail "per-case results differ"
diff <(strip target/fw-run.txt) <(strip target/fw-run-soft.txt) || fail "soft-sqrt results differ"
echo "OK: bit-identical results on x86_64 and on the emulated Cortex-M4F (with and without VSQRT)"
