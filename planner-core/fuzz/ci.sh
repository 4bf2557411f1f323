#!/usr/bin/env bash
# Short bounded fuzz run for CI: every fuzz target of the repository for FUZZ_SECONDS
# (default 10 s) on its committed corpus, single job. Exits non-zero on any crash, hang
# (-timeout) or leak, and when the nightly toolchain or cargo-fuzz cannot be had.
#
# Fuzz crates (each its own workspace, excluded from the main one) and their targets:
#   planner-core/fuzz: map_parser plan_any optimizer_any search_inflate dwa_step anyangle
#   planner-ipc/fuzz:  request_bytes (the service's request handling below the transport)
#   host-sim/fuzz:     ros_map (the ROS map_server YAML + PGM/PNG loader)
set -euo pipefail
cd "$(dirname "$0")/../.."

SECONDS_PER_TARGET="${FUZZ_SECONDS:-10}"

# "crate directory:target"
TARGETS=(
    planner-core/fuzz:map_parser
    planner-core/fuzz:plan_any
    planner-core/fuzz:optimizer_any
    planner-core/fuzz:search_inflate
    planner-core/fuzz:dwa_step
    planner-core/fuzz:anyangle
    planner-ipc/fuzz:request_bytes
    host-sim/fuzz:ros_map
)

if ! rustup run nightly rustc --version >/dev/null 2>&1; then
    echo "fuzz/ci.sh: the nightly toolchain is required (rustup toolchain install nightly)" >&2
    exit 1
fi
if ! cargo fuzz --version >/dev/null 2>&1; then
    echo "fuzz/ci.sh: installing cargo-fuzz"
    cargo install cargo-fuzz --locked
fi
cargo fuzz --version

# One target directory for the three fuzz crates: they share planner-core and (planner-ipc,
# host-sim) iceoryx2, which are then built once under the sanitizer flags.
TARGET_DIR="$PWD/target/fuzz-ci"
for dir in planner-core/fuzz planner-ipc/fuzz host-sim/fuzz; do
    (cd "$dir" && cargo +nightly fuzz build -O --target-dir "$TARGET_DIR")
done
for entry in "${TARGETS[@]}"; do
    dir="${entry%%:*}"
    t="${entry#*:}"
    echo "==> fuzz $dir $t for ${SECONDS_PER_TARGET}s"
    # Work on a scratch copy so that the run does not grow the committed corpus.
    scratch="$(mktemp -d)"
    cp -r "$dir/corpus/$t/." "$scratch/"
    if ! (cd "$dir" && cargo +nightly fuzz run -O --target-dir "$TARGET_DIR" "$t" "$scratch" -- \
        -max_total_time="$SECONDS_PER_TARGET" -timeout=10 -rss_limit_mb=2048 \
        -print_final_stats=1 2>"$scratch.log"); then
        tail -n 60 "$scratch.log" >&2
        echo "fuzz/ci.sh: target $t failed (crash input under $dir/artifacts/$t/)" >&2
        exit 1
    fi
    grep -E '^(Done|stat::number_of_executed_units)' "$scratch.log" || true
    rm -rf "$scratch" "$scratch.log"
done
echo "fuzz/ci.sh: ${#TARGETS[@]} targets, no crash"
