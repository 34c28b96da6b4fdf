"""python-cmaes 0.9 (Debian python3-cmaes) on the problems of cmaes_bench.cpp.

Prints one JSON object {"sphere": [evaluations per seed], "rosenbrock": [...]}: evaluations until
f <= 1e-8, for seeds 0..9, same start, step size and bounds as the C++ side.
"""
import json
import sys

import numpy as np
from cmaes import CMA

DIM, TARGET, MAX_EVALS = 10, 1e-8, 200000
PROBLEMS = {
    "sphere": (lambda x: float(np.sum(x * x)), np.full(DIM, 3.0), 1.0),
    "rosenbrock": (lambda x: float(np.sum(100.0 * (x[1:] - x[:-1] ** 2) ** 2 + (1.0 - x[:-1]) ** 2)), np.zeros(DIM), 0.5),
}

out = {}
for name, (f, x0, sigma0) in PROBLEMS.items():
    counts = []
    for seed in range(int(sys.argv[1]) if len(sys.argv) > 1 else 10):
        opt = CMA(mean=x0.copy(), sigma=sigma0, bounds=np.array([[-10.0, 10.0]] * DIM), seed=seed)
        evals, done = 0, False
        while not done and evals < MAX_EVALS:
            solutions = []
            for _ in range(opt.population_size):
                x = opt.ask()
                value = f(x)
                evals += 1
                solutions.append((x, value))
                if value <= TARGET:
                    done = True
                    break
            if not done:
                opt.tell(solutions)
        counts.append(evals)
    out[name] = counts
print(json.dumps(out))
