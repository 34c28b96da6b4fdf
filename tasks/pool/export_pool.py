#!/usr/bin/env python3
"""Exports a recorded pool (one campaign stage) to the table the pool task and the replay bench read.

Reads the stage's trials with `podium export CAMPAIGN --format json` and the task's parameter box,
features and strategy threshold with `podium tasks TASK --json` (the task's default config: the
stage must have searched the task's default box, as the recorded high-jump pool does). Only
reads the database. Each finished trial becomes a row: its take-off parameters, success by
--success (a JSON pointer into the trial's result info; default: the task's declared success rule,
for the jump its deterministic test jump cleared the starting bar), its strategy feature, the bar it reached and its nearest captured
technique; a trial that failed outright is a row with "finished": false; running or pending
trials are left out (export again as the pool grows).

A second feature set, counted beside the first (for the jump, the 3-D bar-frame rotation of its
Stage 2): --orientation POINTER (a JSON pointer into the result info; for --task jump by default
/bar_frame_rotation, "" for none) with --orientation-config CONFIG, the task config whose
description declares those features and their threshold (for the jump by default {"stage": "novel"}).

A pool may come from several campaigns (e.g. one continued under a new seed): --append TABLE keeps
that table's rows from other campaigns, replaces its rows from this one (exporting again is safe),
and lists every campaign in "source"; each row names its campaign. The tables must describe the same
box, features and strategy threshold.

usage: export_pool.py --podium BIN --db DB --campaign NAME --stage NAME --out TABLE.json
                      [--task jump] [--success POINTER] [--bar /z_reached_m] [--append TABLE]
                      [--orientation POINTER] [--orientation-config JSON]
"""
import argparse
import json
import subprocess
import sys


def pointer(obj, path):
    """The value at JSON pointer `path` in obj, or None."""
    for key in [p for p in path.split("/")[1:]]:
        key = key.replace("~1", "/").replace("~0", "~")
        if isinstance(obj, dict) and key in obj:
            obj = obj[key]
        else:
            return None
    return obj


def run_json(cmd):
    out = subprocess.run(cmd, check=False, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"export_pool: {' '.join(cmd)} failed (exit {out.returncode}): {out.stderr.strip()}")
    return json.loads(out.stdout)


def appended(path, table, campaign):
    """`table` after the rows (and sources) of the table at `path` that come from other campaigns."""
    with open(path, encoding="utf-8") as f:
        old = json.load(f)
    for key in ("params", "features", "strategy_threshold") + (("orientation",) if "orientation" in old else ()):
        if old.get(key) != table.get(key):
            sys.exit(f"export_pool: {path}: {key} is {json.dumps(old.get(key))}, not this export's {json.dumps(table.get(key))}")
    sources = old.get("source", [])
    sources = sources if isinstance(sources, list) else [sources]
    kept_sources = [s for s in sources if s.get("campaign") != campaign]
    kept_campaigns = {s.get("campaign") for s in kept_sources}
    kept = []
    for i, r in enumerate(old.get("rows", [])):
        name = r.get("campaign", sources[0].get("campaign") if len(sources) == 1 else None)
        if name is None:
            sys.exit(f"export_pool: {path}: rows[{i}] names no campaign and the table has {len(sources)} sources")
        if name in kept_campaigns:
            kept.append(dict(r, campaign=name))
    table["source"] = kept_sources + table["source"]
    table["rows"] = kept + table["rows"]
    return table


def main():
    a = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    a.add_argument("--podium", required=True)
    a.add_argument("--db", required=True)
    a.add_argument("--campaign", required=True)
    a.add_argument("--stage", required=True)
    a.add_argument("--out", required=True)
    a.add_argument("--task", default="jump")
    a.add_argument("--success", default=None, help="default: the task's success rule (its description's success.info)")
    a.add_argument("--bar", default="/z_reached_m")
    a.add_argument("--append", default=None, help="a table whose rows of other campaigns are kept")
    a.add_argument("--orientation", default=None, help="JSON pointer of a second feature set in the result info")
    a.add_argument("--orientation-config", default=None, help="the task config that declares the second feature set")
    args = a.parse_args()
    if args.orientation is None:
        args.orientation = "/bar_frame_rotation" if args.task == "jump" else ""
    if args.orientation_config is None:
        args.orientation_config = '{"stage": "novel"}' if args.task == "jump" else "{}"
    task = run_json([args.podium, "tasks", args.task, "--json", "--db", args.db])
    if args.success is None:
        rule = task.get("success") or {}
        if not isinstance(rule.get("info"), str) or "min" in rule:
            sys.exit(f"export_pool: task {args.task} declares no success rule read as true/false ({rule!r}); pass --success")
        args.success = rule["info"]
    if not args.success.startswith("/") or not args.bar.startswith("/"):
        sys.exit("export_pool: --success and --bar are JSON pointers (they start with '/')")

    orientation = None
    if args.orientation:
        if not args.orientation.startswith("/"):
            sys.exit("export_pool: --orientation is a JSON pointer (it starts with '/')")
        described = run_json([args.podium, "tasks", args.task, "--json", "--db", args.db, "--config", args.orientation_config])
        orientation = {"info": args.orientation, "features": described["features"],
                       "strategy_threshold": described["strategy_threshold"],
                       "described_with": json.loads(args.orientation_config)}
    trials = run_json([args.podium, "export", args.campaign, "--format", "json", "--db", args.db])
    names = [p["name"] for p in task["params"]]
    features = [f["name"] for f in task["features"]]
    rows = []
    for t in sorted((t for t in trials if t["stage"] == args.stage), key=lambda t: t["trial"]):
        if t["state"] not in ("done", "failed"):
            continue
        missing = [n for n in names if n not in t["params"]]
        if missing:
            sys.exit(f"export_pool: trial {t['name']}: params lack {missing} (was the stage run on task {args.task}?)")
        row = {"campaign": args.campaign, "trial": t["trial"], "params": [t["params"][n] for n in names]}
        info = t.get("result") or {}
        if t["state"] == "failed":
            row.update(finished=False, success=False, features=None, bar_m=0.0, error=t.get("error", ""))
        else:
            success = pointer(info, args.success)
            if not isinstance(success, (bool, int, float)):
                sys.exit(f"export_pool: trial {t['name']}: result{args.success} is {success!r}, not true/false")
            bar = pointer(info, args.bar)
            row.update(finished=True, success=bool(success) if isinstance(success, bool) else success >= 0.5,
                       features=[t["features"][f] for f in features],
                       bar_m=float(bar) if isinstance(bar, (int, float)) else 0.0)
            technique = pointer(info, "/nearest_technique/name")
            if technique:
                row["technique"] = technique
            if orientation:
                value = pointer(info, args.orientation)
                ok = isinstance(value, list) and len(value) == len(orientation["features"])
                row["orientation"] = value if ok else None
        rows.append(row)
    if not rows:
        sys.exit(f"export_pool: campaign {args.campaign} stage {args.stage} has no finished trials yet")
    table = {
        "source": [{"campaign": args.campaign, "stage": args.stage, "task": args.task, "success": args.success,
                    "recorded": len(rows), "trials_in_stage": sum(1 for t in trials if t["stage"] == args.stage)}],
        "params": task["params"],
        "features": task["features"],
        "strategy_threshold": task["strategy_threshold"],
        "rows": rows,
    }
    if orientation:
        table["orientation"] = orientation
    if args.append:
        table = appended(args.append, table, args.campaign)
    with open(args.out, "w", encoding="utf-8") as f:
        json.dump(table, f, indent=1)
        f.write("\n")
    rows = table["rows"]
    done = sum(r["finished"] for r in rows)
    print(f"{args.out}: {len(rows)} rows ({done} finished, {sum(r['success'] for r in rows)} successful)")

if __name__ == "__main__":
    main()
