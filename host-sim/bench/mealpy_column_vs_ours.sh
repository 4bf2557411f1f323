#!/usr/bin/env bash
# `Lei2024Warehouse`'s column encoding on its 40x40 warehouse map (`host-sim maps`), start (0,0), goal (39,39):
# our HHO and TCLHHO (`host-sim plan --encoding column --no-prune`, release build) against
# mealpy's OriginalHHO on the identical objective written in Python
# (host-sim/bench/mealpy_column.py), population 30, 500 iterations, RUNS runs each (default
# 20; run k uses seed SEED + k). The Python objective is first checked against ours on 300
# random vectors (the `column_cost` example). Not run in CI.
#
# Usage: host-sim/bench/mealpy_column_vs_ours.sh [RUNS] [SEED]
# Needs python3 (3.11) and network access to PyPI on first use: mealpy is installed into its
# own virtual environment, target/mealpy-venv.
#
# Columns: median wall-clock time per run (ours: `time_us` of the planner call; mealpy:
# `solve` alone), median best length over the successful runs, success rate (a run whose best
# still touches a blocked cell fails), and the speed ratio mealpy time / our time.
set -euo pipefail

RUNS="${1:-20}"
SEED="${2:-0}"
POP=30
ITERS=500
START=0,0
GOAL=39,39

ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$ROOT"
OUT="$ROOT/target/mealpy-column"
MAP="$ROOT/target/maps/seed000-warehouse-40.map"
mkdir -p "$OUT"

. "$ROOT/host-sim/bench/mealpy_env.sh"

cargo build --release --quiet -p host-sim
cargo build --release --quiet -p planner-core --example column_cost
BIN="$ROOT/target/release/host-sim"
if [ ! -f "$MAP" ]; then
    "$BIN" maps --out "$ROOT/target/maps" > /dev/null
fi

"$VENV/bin/python" "$ROOT/host-sim/bench/mealpy_column.py" validate "$MAP" "$START" "$GOAL" \
    "$ROOT/target/release/examples/column_cost" 300

for algo in hho tclhho; do
    : > "$OUT/ours_$algo.jsonl"
    for k in $(seq 0 $((RUNS - 1))); do
        "$BIN" plan --map "$MAP" --start "$START" --goal "$GOAL" --algo "$algo" --encoding column \
            --no-prune --pop "$POP" --iters "$ITERS" --seed $((SEED + k)) >> "$OUT/ours_$algo.jsonl"
    done
done
"$VENV/bin/python" "$ROOT/host-sim/bench/mealpy_column.py" run "$MAP" "$START" "$GOAL" "$RUNS" "$SEED" \
    "$POP" "$ITERS" > "$OUT/mealpy_hho.json"

"$VENV/bin/python" - "$OUT" "$MEALPY_VERSION" "$RUNS" <<'PY'
import json, statistics, sys
out, version, runs = sys.argv[1], sys.argv[2], sys.argv[3]
def med(v):
    return statistics.median(v) if v else float("nan")
def ours(a):
    rows = [json.loads(l) for l in open(f"{out}/ours_{a}.jsonl") if l.strip()]
    ok = [r for r in rows if "error" not in r]
    return med([r["time_us"] / 1e6 for r in rows]), med([r["length"] for r in ok]), len(ok), len(rows)
d = json.load(open(f"{out}/mealpy_hho.json"))["runs"]
ok = [r for r in d if r["success"]]
ref = (med([r["time_s"] for r in d]), med([r["length"] for r in ok]), len(ok), len(d))
print(f"Lei2024Warehouse column encoding, seed000-warehouse-40.map (0,0) -> (39,39), D = 40, pop 30, "
      f"500 iterations, {runs} runs; mealpy {version}")
print(f"{'algorithm':<22}{'median time/run':>17}{'median best length':>20}{'success':>10}{'speed-up':>12}")
for name, (t, l, s, n) in [("ours HHO", ours("hho")), ("ours TCLHHO", ours("tclhho")),
                           ("mealpy OriginalHHO", ref)]:
    speed = f"{ref[0] / t:.0f}x" if name.startswith("ours") else ""
    print(f"{name:<22}{t * 1e3:>14.2f} ms{l:>20.4f}{f'{s}/{n}':>10}{speed:>12}")
PY
