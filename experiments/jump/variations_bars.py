#!/usr/bin/env python3
"""Writes the campaign that measures how high each variation's jump policy clears.

At `quick` a Stage 1 trial raises its bar 1 cm per curriculum level and stops after 400k samples,
so the bar it reaches (0.58-0.59 m for every variation) measures the curriculum's progress, not the
body's. This spec jumps each trained policy of `highjump_variations.json` (finished) at a ladder of
bars, in its own world (the variation's config keys), 20 jumps per bar (the evaluate stage: the
first deterministic, 19 with action noise): the highest bar it clears in >= 80% is its figure.

usage: variations_bars.py --podium BIN --db VAR.db --out SPEC.json [--bars 0.58,0.63,...]
then:  podium submit SPEC.json --db bars.db && podium run --db bars.db && podium summary ... --db bars.db
"""
import argparse
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def artifacts(podium, db, campaign):
    """{trial name: {artifact name: path}} from `podium export --format json`."""
    out = subprocess.run([podium, "export", campaign, "--format", "json", "--db", db], capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"variations_bars: {out.stderr.strip()}")
    return {row["name"]: {a["name"]: a["path"] for a in row.get("artifacts", [])} for row in json.loads(out.stdout)}


def main():
    a = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    a.add_argument("--podium", required=True)
    a.add_argument("--db", required=True)
    a.add_argument("--out", required=True)
    a.add_argument("--bars", default="0.58,0.63,0.68,0.73,0.78,0.88,1.0,1.2")
    args = a.parse_args()
    with open(os.path.join(HERE, "highjump_variations.json"), encoding="utf-8") as f:
        variations = json.load(f)
    bars = [float(b) for b in args.bars.split(",")]
    files = artifacts(args.podium, args.db, variations["name"])
    vae = files["pose_vae/0"]["pose_vae"]
    stages = []
    for stage in variations["stages"][1:]:
        box = stage["config"]["takeoff_box"]
        takeoff = [0.5 * (lo + hi) for lo, hi in box.values()]
        policy = files[stage["name"] + "/0"]["policy"]
        world = {k: v for k, v in stage["config"].items() if k in ("gravity_mps2", "strength", "mass_scale", "joint_edits")}
        config = dict(world, stage="evaluate", kind="high_jump",
                      shipped=[{"policy": policy, "pose_vae": vae, "takeoff": takeoff, "z_m": z} for z in bars])
        stages.append({"name": stage["name"], "task": "jump", "preset": "quick", "config": config,
                       "search": {"algorithm": "random"}, "budget": {"trials": len(bars)}})
    spec = {"name": "highjump-variations-bars",
            "description": "Each variation's jump policy (highjump_variations.json) at a ladder of bars, in its own world: "
                           "evaluate trial i jumps bar i, 20 jumps each.",
            "seed": variations["seed"], "workers": 1, "retries": 1, "trial_timeout_s": 600, "stages": stages}
    with open(args.out, "w", encoding="utf-8") as f:
        json.dump(spec, f, indent=1)
        f.write("\n")
    print(f"{args.out}: {len(stages)} stages x {len(bars)} bars")


if __name__ == "__main__":
    main()
