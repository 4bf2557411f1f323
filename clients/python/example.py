"""Example: a 40 x 30 warehouse, A* and TCLHHO, typed errors, then 1,000 A* round trips
timed in Python and, for comparison, through the Rust `planner-client` on the same server.

    python example.py [--prefix planner] [--spawn-server]

--spawn-server starts target/release/planner-server (env PLANNER_SERVER) under a fresh
prefix and stops it at the end; otherwise a server must already serve --prefix.
"""

import argparse
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import planner_client as pc  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
BIN = ROOT / "target" / "release"
START, GOAL = (1, 1), (38, 28)


def warehouse(width=40, height=30):
    """Rows of cells (1 = blocked): two-deep shelves 14 cells long, aisles around them."""
    rows = [[0] * width for _ in range(height)]
    for y in range(3, height - 3):
        if y % 6 in (3, 4):
            for x in list(range(4, 18)) + list(range(22, 36)):
                rows[y][x] = 1
    return rows


def to_movingai(rows):
    lines = ["type octile", f"height {len(rows)}", f"width {len(rows[0])}", "map"]
    return "\n".join(lines + ["".join("@" if c else "." for c in r) for r in rows]) + "\n"


def expect(what, call):
    try:
        call()
        print(f"  {what}: no error?!")
    except pc.PlannerError as e:
        print(f"  {what}: {type(e).__name__} ({type(e).__bases__[0].__name__})")


def rust_client_mean_us(prefix, rows, count):
    """Mean round trip of the Rust planner-client on the same server, map and query: its
    JSON lines carry the server's time only, so the per-request figure is the wall-time
    difference between `count + 1` queries and 1 query (best of 5), over `count`; each
    line it writes (JSON, 52 waypoints) is part of its figure."""
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        (tmp / "w.map").write_text(to_movingai(rows))
        query = f"{START[0]} {START[1]} {GOAL[0]} {GOAL[1]}\n"

        def run(n):
            (tmp / "q.txt").write_text(query * n)
            cmd = [str(BIN / "planner-client"), "--prefix", prefix, "plan", "--map",
                   str(tmp / "w.map"), "--map-id", "9", "--queries", str(tmp / "q.txt"),
                   "--out", str(tmp / "out.jsonl")]
            began = time.perf_counter()
            subprocess.run(cmd, check=True, timeout=60)
            elapsed = time.perf_counter() - began
            lines = [json.loads(line) for line in (tmp / "out.jsonl").read_text().splitlines()]
            assert len(lines) == n and all("path" in line for line in lines), lines[:2]
            return elapsed, lines

        one = min(run(1)[0] for _ in range(5))
        many = [run(count + 1) for _ in range(5)]
        best, lines = min(many, key=lambda m: m[0])
        # A planner-client that reports its round trip per line gives percentiles.
        trips = [line["round_trip_us"] for line in lines if "round_trip_us" in line]
        return (best - one) * 1e6 / count, trips


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--prefix", default="planner")
    parser.add_argument("--spawn-server", action="store_true")
    args = parser.parse_args()
    server = None
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))  # run the finally below
    if args.spawn_server:
        args.prefix = f"py-example-{os.getpid()}"
        path = os.environ.get("PLANNER_SERVER", str(BIN / "planner-server"))
        server = subprocess.Popen([path, "--prefix", args.prefix], stderr=subprocess.DEVNULL)
    try:
        run(args.prefix, open_timeout=5.0 if server else 0.0)
    except pc.NoServer as e:
        sys.exit(f"{e}: start planner-server --prefix {args.prefix}, or use --spawn-server")
    finally:
        if server is not None:
            server.send_signal(signal.SIGTERM)
            server.wait(timeout=10)


def run(prefix, open_timeout):
    rows = warehouse()
    with pc.PlannerClient(prefix, open_timeout=open_timeout) as client:
        info = client.upload_map(1, rows)
        print(f"map {info.map_id} v{info.map_version}: {info.width} x {info.height} cells, "
              f"made usable by the server in {info.decode_us:.1f} us")
        for algo in ("astar", "tclhho"):
            r = client.plan(START, GOAL, algo, seed=7)
            print(f"  {algo:>6}: {len(r.waypoints):2} waypoints, length {r.length:.2f}, "
                  f"{r.turns} turns, {r.evaluations} evaluations, {r.time_us:.0f} us on the server")
        print("typed errors:")
        expect("goal on a shelf", lambda: client.plan(START, (5, 3)))
        expect("unknown map id 42", lambda: client.plan(START, GOAL, map_id=42, version=1))
        expect("radius NaN", lambda: client.plan(START, GOAL, radius=float("nan")))
        expect("population 2^24 + 1",
               lambda: client.plan(START, GOAL, "tclhho", population=(1 << 24) + 1))

        count = 1000
        for _ in range(100):  # warm-up
            client.plan(START, GOAL)
        trips, server = [], []
        for _ in range(count):
            began = time.perf_counter()
            r = client.plan(START, GOAL)
            trips.append((time.perf_counter() - began) * 1e6)
            server.append(r.time_us)
        q = statistics.quantiles(trips, n=100)
        print(f"{count} A* round trips {START} -> {GOAL}, Python client: p50 {q[49]:.1f} us, "
              f"p99 {q[98]:.1f} us, mean {statistics.fmean(trips):.1f} us "
              f"(server's planning: p50 {statistics.median(server):.1f} us)")
        if not (BIN / "planner-client").exists():
            print("no target/release/planner-client: no Rust comparison")
            return
        mean, rust = rust_client_mean_us(prefix, rows, count)
        if rust:
            q = statistics.quantiles(rust, n=100)
            print(f"same with the Rust planner-client: p50 {q[49]:.1f} us, p99 {q[98]:.1f} us")
        print(f"same with the Rust planner-client: mean {mean:.1f} us "
              f"(wall time of {count + 1} queries minus 1 query, per request)")


if __name__ == "__main__":
    main()
