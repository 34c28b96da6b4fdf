#!/usr/bin/python3
"""Trials recorded per second: podium (no-op landscape trials, 2 worker processes, SQLite) beside
Optuna (RandomSampler, SQLite storage, the same number of trials, in one process:
its fastest setting; threads only contend for the SQLite file), run by this script
in one go. Prints each repeat, the medians and the ratio.

usage: bench/orchestrator/throughput.py [--trials N] [--repeats R] [--podium build/bin/podium]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time


def podium_once(podium, trials, seed):
    with tempfile.TemporaryDirectory() as tmp:
        spec = {"name": "throughput", "seed": seed, "workers": 2, "retries": 0,
                "stages": [{"name": "noop", "task": "landscape",
                            "config": {"metric_points": 0},
                            "search": {"algorithm": "random"}, "budget": {"trials": trials}}]}
        with open(os.path.join(tmp, "spec.json"), "w") as f:
            json.dump(spec, f)
        subprocess.run([podium, "submit", "spec.json"], cwd=tmp, check=True, capture_output=True)
        start = time.perf_counter()
        subprocess.run([podium, "run", "--workers", "2"], cwd=tmp, check=True, capture_output=True)
        elapsed = time.perf_counter() - start
        status = json.loads(subprocess.run([podium, "status", "1", "--json"], cwd=tmp, check=True,
                                           capture_output=True).stdout)
        assert status["done"] == trials, status
        return trials / elapsed


def optuna_once(trials, seed):
    import optuna
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    with tempfile.TemporaryDirectory() as tmp:
        storage = "sqlite:///" + os.path.join(tmp, "optuna.db")
        study = optuna.create_study(storage=storage, sampler=optuna.samplers.RandomSampler(seed=seed))
        objective = lambda t: t.suggest_float("x0", 0, 1) + t.suggest_float("x1", 0, 1) + t.suggest_float("x2", 0, 1)
        start = time.perf_counter()
        study.optimize(objective, n_trials=trials)  # n_jobs=1: Optuna's fastest setting here
        elapsed = time.perf_counter() - start
        assert len(study.trials) == trials
        return trials / elapsed


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--trials", type=int, default=1000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--podium", default=os.path.join(os.path.dirname(__file__), "../../build/bin/podium"))
    args = parser.parse_args()
    podium_rates, optuna_rates = [], []
    for r in range(args.repeats):
        podium_rates.append(podium_once(os.path.abspath(args.podium), args.trials, seed=100 + r))
        optuna_rates.append(optuna_once(args.trials, seed=100 + r))
        print(f"repeat {r}: podium {podium_rates[-1]:8.1f} trials/s   optuna {optuna_rates[-1]:6.1f} trials/s", flush=True)
    p, o = statistics.median(podium_rates), statistics.median(optuna_rates)
    print(f"median over {args.repeats} repeats of {args.trials} trials (2 workers, SQLite):")
    print(f"  podium  {p:8.1f} trials/s")
    print(f"  optuna  {o:8.1f} trials/s  (3.1, RandomSampler, one process)")
    print(f"  ratio   {p / o:8.1f}x   (bar: >= 25x)")
    return 0 if p / o >= 25 else 1


if __name__ == "__main__":
    sys.exit(main())
