#!/usr/bin/env python3
"""A finished campaign's canonical fingerprint, to show that a refactoring changed no result.

    scripts/fingerprint_campaign.py fingerprint DB CAMPAIGN [--podium BIN] > before.txt
    scripts/fingerprint_campaign.py run-smoke OUT_DIR [--podium BIN]
    scripts/fingerprint_campaign.py compare BEFORE_DIR AFTER_DIR

`fingerprint` prints, per trial (in stage and trial order): its state, seed, params, objectives,
features, strategy and result info (from `podium export CAMPAIGN --format json`), the sha256 of
every artifact file (policies, recorded motions, ...) and every metric series point by point (from
the dashboard API of `podium serve`: nothing but store/ opens the database), then one sha256 of it
all. Two fingerprints of the same campaign run on two trees diff line by line.

One exception: the P-VAE's TorchScript file (artifact `pose_vae`, learn/'s VAE export) names its
submodules by memory address, so its bytes and the order of its tensors differ between runs of a
seed; for it the fingerprint is the sorted multiset of its tensors' sha256 (`--by-tensors`).

Metric series under `time/` are wall-clock seconds (character/training_stage.h): they differ
between runs of a seed by design, so only their names and point counts are printed, as comment
lines (`# `) after the rest, outside the final sha256. Absolute paths inside the database's run
folders are written relative to them, so campaigns run in two folders compare equal.

`run-smoke` submits and runs, in OUT_DIR/<name>/podium.db, the smoke campaigns the end-to-end tests
run: campaigns/getup.json at the smoke preset (tests/tasks/getup/getup_task_test.cpp),
campaigns/highjump.json and obstaclejump.json cut as in tests/tasks/jump/jump_task_test.cpp, and
the test_pendulum hand-over campaign of tests/orchestrator/handover_campaign_test.cpp; then writes
OUT_DIR/<name>.fingerprint for each; and two campaigns the tests do not run: the high jump with its
bar rising at every iteration (copies rebuilt at new control rates) and get-up on PPO. Every
campaign runs with one worker, so search algorithms that read earlier results (BDS,
novel-policy) see them in the same order on every run. `compare` diffs two such folders'
fingerprints (comment lines aside) and exits 1 if any differs.
"""

import argparse
import difflib
import hashlib
import json
import os
import pathlib
import socket
import subprocess
import sys
import time
import urllib.request
import zipfile

ROOT = pathlib.Path(__file__).resolve().parent.parent


def podium_json(podium, args):
    out = subprocess.run([podium, *args], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


class Dashboard:
    """`podium serve` on a free local port, read-only over the database."""

    def __init__(self, podium, db):
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            self.port = s.getsockname()[1]
        self.process = subprocess.Popen([podium, "serve", "--port", str(self.port), "--host", "127.0.0.1", "--db", str(db)],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        deadline = time.monotonic() + 30
        while True:
            try:
                self.get("/api/version")
                return
            except OSError:
                if self.process.poll() is not None or time.monotonic() > deadline:
                    raise SystemExit("podium serve did not start: " + self.process.stderr.read().decode())
                time.sleep(0.1)

    def get(self, path):
        with urllib.request.urlopen(f"http://127.0.0.1:{self.port}{path}", timeout=60) as response:
            return json.loads(response.read())

    def close(self):
        self.process.terminate()
        self.process.wait()


def relative_paths(value, runs):
    """`value` with every string under the run folders written relative to them."""
    if isinstance(value, dict):
        return {k: relative_paths(v, runs) for k, v in value.items()}
    if isinstance(value, list):
        return [relative_paths(v, runs) for v in value]
    if isinstance(value, str) and value.startswith(runs):
        return "<runs>" + value[len(runs):]
    return value


def line(key, value):
    return key + " " + json.dumps(value, sort_keys=True, separators=(",", ":"))


def tensors_digest(path):
    """sha256 over the sorted sha256 of a TorchScript archive's tensor records (data/*)."""
    with zipfile.ZipFile(path) as archive:
        digests = sorted(hashlib.sha256(archive.read(n)).hexdigest() for n in archive.namelist() if "/data/" in n)
    return hashlib.sha256("\n".join(digests).encode()).hexdigest()


def fingerprint(podium, db, campaign, by_tensors=("pose_vae",)):
    db = pathlib.Path(db).resolve()
    runs = str(db) + ".runs"
    rows = podium_json(podium, ["export", str(campaign), "--format", "json", "--db", str(db)])
    out, times = [], []
    dashboard = Dashboard(podium, db)
    try:
        for row in sorted(rows, key=lambda r: r["id"]):
            name = row["name"]
            for key in ("state", "seed", "params", "objectives", "features", "strategy", "result", "error"):
                out.append(line(f"{name} {key}", relative_paths(row[key], runs)))
            detail = dashboard.get(f"/api/trials/{row['id']}")
            for a in sorted(detail["artifacts"], key=lambda a: a["name"]):
                digest = hashlib.sha256(pathlib.Path(a["path"]).read_bytes()).hexdigest()
                if digest != a["sha256"]:
                    raise SystemExit(f"{name}: artifact {a['name']} changed since the store recorded it")
                if a["name"] in by_tensors:
                    out.append(line(f"{name} artifact {a['name']}", {"tensors_sha256": tensors_digest(a["path"])}))
                else:
                    out.append(line(f"{name} artifact {a['name']}", {"sha256": digest, "size": a["size_bytes"]}))
            for series in sorted(dashboard.get(f"/api/trials/{row['id']}/metrics?max_points=1000000"), key=lambda s: s["name"]):
                if len(series["steps"]) != series["total_points"]:
                    raise SystemExit(f"{name}: metric {series['name']} came back thinned")
                if series["name"].startswith("time/"):
                    times.append("# " + line(f"{name} metric {series['name']}", {"points": series["total_points"]}))
                else:
                    out.append(line(f"{name} metric {series['name']}", [series["steps"], series["values"]]))
    finally:
        dashboard.close()
    digest = hashlib.sha256("\n".join(out).encode()).hexdigest()
    return "\n".join(out + times) + f"\nfingerprint {digest}\n"


def smoke_specs():
    """The campaigns the end-to-end tests run, as they build them."""
    def read(name):
        return json.loads((ROOT / "campaigns" / name).read_text())

    getup = read("getup.json")
    for stage in getup["stages"]:
        stage["preset"] = "smoke"
    getup["trial_timeout_s"] = 300

    def jump(name, explore_trials):
        spec = read(name)
        for stage in spec["stages"]:
            stage["preset"] = "smoke"
        spec["stages"][1]["budget"]["trials"] = explore_trials
        spec["stages"][2]["search"]["config"]["trials_per_input"] = 1
        spec["stages"][2]["budget"]["trials"]["per_input"] = 1
        spec["trial_timeout_s"] = 120
        return spec

    def pendulum_stage(name):
        return {"name": name, "task": "test_pendulum", "preset": "smoke", "config": {"updates": 30, "checkpoint_every": 3},
                "search": {"algorithm": "random"}}

    explore, refine, polish = pendulum_stage("explore"), pendulum_stage("refine"), pendulum_stage("polish")
    explore["budget"] = {"trials": 4}
    refine["budget"] = {"trials": {"per_input": 1}}
    refine["inputs"] = {"stage": "explore", "select": "best_per_strategy", "per_trial": "each"}
    polish["budget"] = {"trials": 2}
    polish["inputs"] = {"stage": "refine", "select": "best"}
    handover = {"name": "pendulum_handover", "seed": 16, "workers": 2, "retries": 3, "trial_timeout_s": 300,
                "stages": [explore, refine, polish]}
    # Beyond the tests' campaigns: the jump's bar rising at every iteration (its copies rebuilt at
    # new control rates mid-trial), and get-up's Weaker on PPO.
    rising = jump("highjump.json", 2)
    for stage in rising["stages"][1:]:
        stage["config"].update({"reward_threshold": 0.01, "total_samples": 640})
    getup_ppo = json.loads(json.dumps(getup))
    getup_ppo["name"] = "getup_ppo"
    getup_ppo["stages"] = getup_ppo["stages"][:2]
    for stage in getup_ppo["stages"]:
        stage["config"].update({"algorithm": "ppo", "ppo": {"hidden": [16, 16], "rollout_steps": 50}})
    return {"getup": getup, "highjump": jump("highjump.json", 4), "obstaclejump": jump("obstaclejump.json", 3),
            "handover": handover, "highjump_rising": rising, "getup_ppo": getup_ppo}


def run_smoke(podium, out_dir, by_tensors):
    out_dir = pathlib.Path(out_dir).resolve()
    for name, spec in smoke_specs().items():
        folder = out_dir / name
        folder.mkdir(parents=True, exist_ok=False)
        (folder / "spec.json").write_text(json.dumps(spec, indent=1))
        campaign = subprocess.run([podium, "submit", "spec.json"], cwd=folder, check=True, capture_output=True,
                                  text=True).stdout.strip()
        started = time.monotonic()
        with open(folder / "run.log", "w") as log:
            subprocess.run([podium, "run", "--workers", "1"], cwd=folder, check=True, stdout=log, stderr=subprocess.STDOUT)
        print(f"{name}: campaign {campaign} ran in {time.monotonic() - started:.0f} s", file=sys.stderr)
        (out_dir / f"{name}.fingerprint").write_text(fingerprint(podium, folder / "podium.db", campaign, by_tensors))


def compare(before_dir, after_dir):
    """Prints, per fingerprint in before_dir, whether after_dir's equals it (comment lines aside)."""
    differ = False
    for before in sorted(pathlib.Path(before_dir).glob("*.fingerprint")):
        after = pathlib.Path(after_dir) / before.name
        kept = [[l for l in f.read_text().splitlines() if not l.startswith("# ")] for f in (before, after)]
        diff = list(difflib.unified_diff(*kept, str(before), str(after), lineterm="", n=0))
        differ |= bool(diff)
        print(f"{before.stem}: {'differs' if diff else 'identical'} ({len(kept[0]) - 1} lines, "
              f"{kept[0][-1].split()[-1][:16]}…)")
        for d in diff:
            print("  " + d[:300])
    return 1 if differ else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--podium", default=str(ROOT / "build" / "bin" / "podium"), help="the podium binary")
    parser.add_argument("--by-tensors", nargs="*", default=["pose_vae"],
                        help="artifacts fingerprinted by their tensors, not their bytes (default: pose_vae)")
    commands = parser.add_subparsers(dest="command", required=True)
    f = commands.add_parser("fingerprint", help="print a finished campaign's fingerprint")
    f.add_argument("db")
    f.add_argument("campaign", help="campaign id or name")
    r = commands.add_parser("run-smoke", help="run the smoke campaigns in OUT_DIR and fingerprint each")
    r.add_argument("out_dir")
    c = commands.add_parser("compare", help="diff two run-smoke folders' fingerprints")
    c.add_argument("before_dir")
    c.add_argument("after_dir")
    args = parser.parse_args()
    if args.command == "fingerprint":
        sys.stdout.write(fingerprint(args.podium, args.db, args.campaign, args.by_tensors))
    elif args.command == "compare":
        sys.exit(compare(args.before_dir, args.after_dir))
    else:
        run_smoke(args.podium, args.out_dir, args.by_tensors)


if __name__ == "__main__":
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    main()
