#!/usr/bin/env python3
"""The column-encoding objective of Lei2024Warehouse (docs/references.md) in Python, for timing mealpy against our planners.

The objective is the one `host-sim plan --encoding column` optimises
(`planner-core/src/encoding/column.rs`), re-implemented exactly:

* variable j is the row of the waypoint in map column `start.x + j`, rounded half away from
  zero (like `roundf`) and clamped to [0, height - 1];
* path start -> (start.x, x_0) -> (start.x + 1, x_1) -> ... -> (goal.x, x_last) -> goal;
* cost = length + penalty * (blocked cells touched, counted per segment), penalty =
  2 * cells + 1000 (`infeasible_penalty`); a cell is touched when the segment meets its closed
  square, even at a corner (SPEC's conservative rule), cells off the map count as blocked;
  integer arithmetic, strip by strip, like `geometry::exact_strips`.

Usage:
  mealpy_column.py validate MAP SX,SY GX,GY COLUMN_COST_BIN [N]
      N random vectors (default 300) through this objective and through the Rust example
      `column_cost`; asserts equal blocked counts and lengths and costs equal to 1e-3.
  mealpy_column.py run MAP SX,SY GX,GY RUNS SEED [POP ITERS]
      mealpy's OriginalHHO, bounds [0, height - 1]^D, RUNS runs with seeds SEED + k; JSON out.
"""
import json
import math
import subprocess
import sys
import time


def load_map(path):
    with open(path) as f:
        lines = f.read().splitlines()
    height = width = None
    k = 0
    while lines[k].strip() != "map":
        key, _, val = lines[k].partition(" ")
        if key == "height":
            height = int(val)
        elif key == "width":
            width = int(val)
        k += 1
    rows = lines[k + 1:k + 1 + height]
    # Moving AI: '.', 'G', 'S' are passable; everything else is blocked (as in grid.rs).
    blocked = [[c not in ".GS" for c in row[:width]] for row in rows]
    return width, height, blocked


class ColumnObjective:
    def __init__(self, map_path, start, goal):
        self.width, self.height, blocked = load_map(map_path)
        self.start, self.goal = start, goal
        self.dim = goal[0] - start[0] + 1
        self.penalty = 2.0 * self.width * self.height + 1000.0
        w, h = self.width, self.height
        # Prefix sums: row_pre[y][x] = blocked cells in row y, columns < x; col_pre likewise.
        self.row_pre = []
        for y in range(h):
            acc = [0]
            for x in range(w):
                acc.append(acc[-1] + blocked[y][x])
            self.row_pre.append(acc)
        self.col_pre = []
        for x in range(w):
            acc = [0]
            for y in range(h):
                acc.append(acc[-1] + blocked[y][x])
            self.col_pre.append(acc)

    def _run_count(self, pre, line, n_lines, n_along, lo, hi):
        """Blocked cells in cells lo..=hi of one row/column (`line`); off-map cells count."""
        if lo > hi:
            return 0
        total = hi - lo + 1
        if line < 0 or line >= n_lines:
            return total
        ilo, ihi = max(lo, 0), min(hi, n_along - 1)
        if ilo > ihi:
            return total
        p = pre[line]
        return (total - (ihi - ilo + 1)) + p[ihi + 1] - p[ilo]

    def _strips(self, a, b, pre, n_lines, n_along):
        """`exact_strips` of geometry.rs: segment between lattice points a=(u, v), b."""
        (u0, v0), (u1, v1) = (a, b) if a[0] <= b[0] else (b, a)
        du, dv = u1 - u0, v1 - v0
        if du == 0:
            return self._run_count(pre, u0, n_lines, n_along, min(v0, v1), max(v0, v1))
        count = 0
        two_du = 2 * du
        for s in range(u0, u1 + 1):
            left2 = max(2 * s - 1, 2 * u0)
            right2 = min(2 * s + 1, 2 * u1)
            h_left = two_du * v0 + (left2 - 2 * u0) * dv
            h_right = two_du * v0 + (right2 - 2 * u0) * dv
            lo, hi = (h_left, h_right) if h_left <= h_right else (h_right, h_left)
            # ceil((lo - du) / 2du) .. floor((hi + du) / 2du), exact in integers.
            first = -((du - lo) // two_du)
            last = (hi + du) // two_du
            count += self._run_count(pre, s, n_lines, n_along, first, last)
        return count

    def blocked_touched(self, a, b):
        (ax, ay), (bx, by) = a, b
        if abs(by - ay) > abs(bx - ax):
            # Strips are columns: u = x, v = y.
            return self._strips((ax, ay), (bx, by), self.col_pre, self.width, self.height)
        # Strips are rows: u = y, v = x.
        return self._strips((ay, ax), (by, bx), self.row_pre, self.height, self.width)

    def row(self, v):
        v = float(v)
        if v != v:  # NaN -> 0, like the Rust clamp
            return 0
        r = math.floor(v + 0.5) if v >= 0 else -math.floor(-v + 0.5)  # roundf
        return int(min(max(r, 0), self.height - 1))

    def length_and_blocked(self, x):
        length = 0.0
        blocked = 0
        prev = self.start
        x0 = self.start[0]
        for j in range(self.dim):
            cell = (x0 + j, self.row(x[j]))
            length += math.hypot(cell[0] - prev[0], cell[1] - prev[1])
            blocked += self.blocked_touched(prev, cell)
            prev = cell
        length += math.hypot(self.goal[0] - prev[0], self.goal[1] - prev[1])
        blocked += self.blocked_touched(prev, self.goal)
        return length, blocked

    def __call__(self, x):
        length, blocked = self.length_and_blocked(x)
        return length + self.penalty * blocked


def cell_arg(s):
    x, y = s.split(",")
    return int(x), int(y)


def validate(obj, bin_path, map_path, start, goal, n):
    import numpy as np

    rng = np.random.default_rng(12345)
    top = obj.height - 1
    vectors = []
    for k in range(n):
        kind = k % 5
        if kind == 0:
            v = rng.uniform(0, top, obj.dim)
        elif kind == 1:  # integral rows
            v = rng.integers(0, top + 1, obj.dim).astype(float)
        elif kind == 2:  # exact halves: the rounding rule
            v = rng.integers(0, top, obj.dim) + 0.5
        elif kind == 3:  # out of the box: the clamp
            v = rng.uniform(-5, top + 5, obj.dim)
        else:  # mostly feasible: along free rows, jumping rows only between free columns
            free_rows = [y for y in range(obj.height) if obj.row_pre[y][-1] == 0]
            free_cols = [x for x in range(obj.width) if obj.col_pre[x][-1] == 0]
            r = rng.choice(free_rows)
            v = np.empty(obj.dim)
            for j in range(obj.dim):
                col = start[0] + j
                if col in free_cols and col - 1 in free_cols and rng.random() < 0.5:
                    r = rng.choice(free_rows)
                v[j] = r + rng.uniform(-0.45, 0.45)
        vectors.append(v.astype(np.float32))  # exactly the f32 values Rust reads
    text = "\n".join(" ".join(repr(float(c)) for c in v) for v in vectors) + "\n"
    out = subprocess.run([bin_path, map_path, f"{start[0]},{start[1]}", f"{goal[0]},{goal[1]}"],
                         input=text, capture_output=True, text=True, check=True).stdout.splitlines()
    assert out[0] == f"penalty {obj.penalty:g}" or float(out[0].split()[1]) == obj.penalty, out[0]
    worst = 0.0
    feasible = 0
    for v, line in zip(vectors, out[1:], strict=True):
        length_rs, blocked_rs, cost_rs = line.split()
        length_rs, blocked_rs, cost_rs = float(length_rs), int(blocked_rs), float(cost_rs)
        length_py, blocked_py = obj.length_and_blocked([float(c) for c in v])
        cost_py = obj(v)
        assert blocked_py == blocked_rs, (v, blocked_py, blocked_rs)
        assert abs(length_py - length_rs) <= 1e-3, (v, length_py, length_rs)
        # The f64 total from Rust's parts; Rust's own f32 total within f32 rounding of it.
        assert abs(cost_py - (length_rs + obj.penalty * blocked_rs)) <= 1e-3, (v, cost_py)
        assert abs(cost_py - cost_rs) <= max(1e-3, 2e-7 * cost_py), (v, cost_py, cost_rs)
        worst = max(worst, abs(length_py - length_rs))
        feasible += blocked_py == 0
    print(f"validated {n} vectors ({feasible} feasible): blocked counts equal, "
          f"max |length difference| {worst:.2e}")


def run_mealpy(obj, runs, seed, pop, iters):
    from mealpy import FloatVar, HHO

    results = []
    for k in range(runs):
        problem = {
            "obj_func": obj,
            "bounds": FloatVar(lb=[0.0] * obj.dim, ub=[float(obj.height - 1)] * obj.dim),
            "minmax": "min",
            "log_to": None,
        }
        model = HHO.OriginalHHO(epoch=iters, pop_size=pop)
        t0 = time.perf_counter()
        best = model.solve(problem, seed=seed + k)
        elapsed = time.perf_counter() - t0
        length, blocked = obj.length_and_blocked(best.solution)
        results.append({"seed": seed + k, "time_s": elapsed, "cost": float(best.target.fitness),
                        "length": length, "blocked": blocked, "success": blocked == 0})
    print(json.dumps({"algo": "mealpy OriginalHHO", "pop": pop, "iters": iters, "runs": results}))


def main():
    mode = sys.argv[1]
    map_path, start, goal = sys.argv[2], cell_arg(sys.argv[3]), cell_arg(sys.argv[4])
    obj = ColumnObjective(map_path, start, goal)
    if mode == "validate":
        n = int(sys.argv[6]) if len(sys.argv) > 6 else 300
        validate(obj, sys.argv[5], map_path, start, goal, n)
    elif mode == "run":
        runs, seed = int(sys.argv[5]), int(sys.argv[6])
        pop = int(sys.argv[7]) if len(sys.argv) > 7 else 30
        iters = int(sys.argv[8]) if len(sys.argv) > 8 else 500
        run_mealpy(obj, runs, seed, pop, iters)
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    main()
