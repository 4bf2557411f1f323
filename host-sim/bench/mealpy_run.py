#!/usr/bin/env python3
"""Runs mealpy's OriginalHHO / OriginalGWO on the shifted sphere and prints JSON.

Usage: mealpy_run.py ALGO DIM SHIFT POP ITERS RUNS SEED
Each run k uses numpy/mealpy seed SEED + k. Time per run is wall-clock of `solve` alone.
"""
import json
import sys
import time

import numpy as np
from mealpy import FloatVar, GWO, HHO


def main():
    algo, dim, shift, pop, iters, runs, seed = sys.argv[1:8]
    dim, shift, pop, iters, runs, seed = int(dim), float(shift), int(pop), int(iters), int(runs), int(seed)

    def sphere(x):
        return float(np.sum((x - shift) ** 2))

    results = []
    for k in range(runs):
        problem = {
            "obj_func": sphere,
            "bounds": FloatVar(lb=[-100.0] * dim, ub=[100.0] * dim),
            "minmax": "min",
            "log_to": None,
        }
        if algo == "hho":
            model = HHO.OriginalHHO(epoch=iters, pop_size=pop)
        elif algo == "gwo":
            model = GWO.OriginalGWO(epoch=iters, pop_size=pop)
        else:
            raise SystemExit(f"unknown algo {algo}")
        start = time.perf_counter()
        best = model.solve(problem, seed=seed + k)
        elapsed = time.perf_counter() - start
        results.append({"best_cost": float(best.target.fitness), "time_s": elapsed})
    costs = sorted(r["best_cost"] for r in results)
    times = sorted(r["time_s"] for r in results)
    n = len(costs)
    median = lambda v: v[n // 2] if n % 2 else (v[n // 2 - 1] + v[n // 2]) / 2
    print(json.dumps({"algo": algo, "runs": results, "median_best_cost": median(costs), "median_time_s": median(times)}))


if __name__ == "__main__":
    main()
