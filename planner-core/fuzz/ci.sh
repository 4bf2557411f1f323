#!/usr/bin/env bash
# Short bounded fuzz run for CI: every planner-core target for FUZZ_SECONDS (default 25 s)
# on its committed corpus, single job. Exits non-zero on any crash, hang (-timeout) or
# leak, and when the nightly toolchain or cargo-fuzz cannot be had.
set -euo pipefail
cd "$(dirname "$0")"

SECONDS_PER_TARGET="${FUZZ_SECONDS:-25}"

# planner-core's targets. Targets of other components (DWA step, ROS YAML/PGM map loader,
# planner service request handling) are appended to this list when they land.
TARGETS=(
    map_parser
    plan_any
    optimizer_any
    search_inflate
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

cargo +nightly fuzz build -O
for t in "${TARGETS[@]}"; do
    echo "==> fuzz $t for ${SECONDS_PER_TARGET}s"
    # Work on a scratch copy so that the run does not grow the committed corpus.
    scratch="$(mktemp -d)"
    cp -r "corpus/$t/." "$scratch/"
    if ! cargo +nightly fuzz run -O "$t" "$scratch" -- \
        -max_total_time="$SECONDS_PER_TARGET" -timeout=10 -rss_limit_mb=2048 \
        -print_final_stats=1 2>"$scratch.log"; then
        tail -n 60 "$scratch.log" >&2
        echo "fuzz/ci.sh: target $t failed (crash input under fuzz/artifacts/$t/)" >&2
        exit 1
    fi
    grep -E '^(Done|stat::number_of_executed_units)' "$scratch.log" || true
    rm -rf "$scratch" "$scratch.log"
done
echo "fuzz/ci.sh: ${#TARGETS[@]} targets, no crash"
