#!/usr/bin/env python3
"""The recorded high-jump pool's own figures, beside its replay (tasks/pool/README.md):

- compute: per pool campaign, the take-offs recorded, their summed and median wall time (every
  attempt's), and the rest (P-VAE, unfinished trials), from the database's attempts;
- repeatability: for each stage `repeat_poolK` of the repeats campaign
  (experiments/jump/highjump_pool_repeats.json), the pool's take-off K (its row in the table) beside
  its retrainings: success at the starting bar, bar reached, up-angle and 3-D bar-frame rotation;
  per take-off the up-angle's spread (sd over the pool row and its repeats), the rotations'
  largest pairwise distance and whether the success agrees, and over all of them the pooled within-take-off sd of the up-angle against the
  strategy threshold.

Reads the database read-only (its attempts; the trials through `podium export --format json`: give a
copy of a database in use, `sqlite3 'file:pool.db?mode=ro' ".backup copy.db"`).

Usage: experiments/jump/pool_report.py --podium build/bin/podium --db copy.db
         --table experiments/jump/highjump_pool_table.json
         [--pool highjump-pool-2 --pool highjump-pool-3] [--repeats highjump-pool-repeats] [--of highjump-pool-2]
"""
import argparse
import json
import math
import sqlite3
import statistics
import subprocess
import sys


def export(podium, db, campaign):
    out = subprocess.run([podium, "export", str(campaign), "--format", "json", "--db", db],
                         capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"pool_report: podium export {campaign}: {out.stderr.strip()}")
    return json.loads(out.stdout)


def compute(db, campaigns):
    """Every attempt's wall time (interrupted ones too: a resumed trial continues from its checkpoint)."""
    con = sqlite3.connect(f"file:{db}?mode=ro", uri=True)
    print("compute (the summed wall time of every attempt, from the database):")
    total_h = 0.0
    for name in campaigns:
        rows = con.execute(
            "SELECT s.name, t.id, t.state, SUM(CASE WHEN a.finished_at > 0 THEN a.finished_at - a.started_at ELSE 0 END) "
            "FROM trials t JOIN stages s ON s.id = t.stage_id JOIN attempts a ON a.trial_id = t.id "
            "WHERE s.campaign_id = (SELECT MAX(id) FROM campaigns WHERE name = ?) GROUP BY t.id", (name,)).fetchall()
        pool = [sec / 60.0 for stage, _, state, sec in rows if stage == "pool" and state == "done"]
        other = sum(sec for stage, _, state, sec in rows if not (stage == "pool" and state == "done")) / 60.0
        hours = (sum(pool) + other) / 60.0
        total_h += hours
        print(f"  {name}: {len(pool)} take-offs, {sum(pool) / 60.0:.1f} h (median {statistics.median(pool) if pool else 0:.1f} "
              f"min per take-off); the P-VAE and unfinished or failed trials {other:.1f} min")
    print(f"  these campaigns: {total_h:.1f} h of trial wall time")


def outcome(trial):
    r = trial.get("result") or {}
    start = r.get("start_bar") or {}
    return {"success": bool(start.get("deterministic_success")), "bar_m": r.get("z_reached_m"),
            "up_angle": (trial.get("features") or {}).get("up_angle_rad"),
            "rotation": r.get("bar_frame_rotation")}


def fmt(o):
    rot = "[" + ", ".join(f"{x:+.2f}" for x in o["rotation"]) + "]" if o.get("rotation") else "—"
    up = f"{o['up_angle']:.3f}" if o.get("up_angle") is not None else "—"
    return f"success {'yes' if o['success'] else 'no ':3}  bar {o['bar_m']:.2f} m  up-angle {up} rad  rotation {rot}"


def repeatability(podium, db, repeats, pool_campaign, table_file):
    table = json.load(open(table_file))
    threshold = table["strategy_threshold"]
    rows = {(r["campaign"], r["trial"]): r for r in table["rows"]}
    trials = export(podium, db, repeats)
    stages = sorted({t["stage"] for t in trials if t["stage"].startswith("repeat_pool")},
                    key=lambda s: int(s[len("repeat_pool"):]))
    print(f"\nrepeatability (pool campaign {pool_campaign}; strategy threshold τ = {threshold} rad):")
    squares, dof, agree, counted = 0.0, 0, 0, 0
    ok_squares, ok_dof = 0.0, 0  # over the successful trainings only: the features a count sees
    for stage in stages:
        k = int(stage[len("repeat_pool"):])
        row = rows.get((pool_campaign, k))
        done = [t for t in trials if t["stage"] == stage and t["state"] == "done"]
        if row is None or not done:
            print(f"  take-off {k}: {'not in the table' if row is None else 'no repeat finished yet'}")
            continue
        first = {"success": row["success"], "bar_m": row["bar_m"],
                 "up_angle": row["features"][0] if row.get("features") else None, "rotation": row.get("orientation")}
        runs = [first] + [outcome(t) for t in done]
        print(f"  take-off {k} {['%.3f' % x for x in row['params']]}:")
        print(f"    pool     {fmt(first)}")
        for t, o in zip(done, runs[1:]):
            print(f"    repeat {t['trial']} {fmt(o)}")
        ups = [o["up_angle"] for o in runs if o["up_angle"] is not None]
        if len(ups) >= 2:
            sd = statistics.stdev(ups)
            mean = statistics.fmean(ups)
            squares += sum((u - mean) ** 2 for u in ups)
            dof += len(ups) - 1
            print(f"    up-angle {mean:.3f} ± {sd:.3f} rad over {len(ups)} trainings; "
                  f"range {max(ups) - min(ups):.3f} rad ({(max(ups) - min(ups)) / threshold:.2f} τ)")
        ok = [o["up_angle"] for o in runs if o["success"] and o["up_angle"] is not None]
        if len(ok) >= 2:
            ok_squares += sum((u - statistics.fmean(ok)) ** 2 for u in ok)
            ok_dof += len(ok) - 1
        rots = [o["rotation"] for o in runs if o.get("rotation")]
        if len(rots) >= 2:
            far = max(math.dist(a, b) for a in rots for b in rots)
            tau_r = table.get("orientation", {}).get("strategy_threshold")
            print(f"    rotation: largest pairwise distance {far:.3f} rad" + (f" ({far / tau_r:.2f} τ)" if tau_r else ""))
        same = len({o["success"] for o in runs}) == 1
        agree += same
        counted += 1
        print(f"    success {'agrees' if same else 'differs'} over {len(runs)} trainings "
              f"({sum(o['success'] for o in runs)} of {len(runs)} succeed)")
    if dof:
        pooled = math.sqrt(squares / dof)
        print(f"  pooled within-take-off sd of the up-angle: {pooled:.3f} rad ({pooled / threshold:.2f} τ), "
              f"{dof} degrees of freedom; success agrees for {agree} of {counted} take-offs")
    if ok_dof:
        pooled = math.sqrt(ok_squares / ok_dof)
        print(f"  over the successful trainings only (what a strategy count sees): {pooled:.3f} rad "
              f"({pooled / threshold:.2f} τ), {ok_dof} degrees of freedom")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--podium", required=True)
    p.add_argument("--db", required=True)
    p.add_argument("--table", required=True)
    p.add_argument("--pool", action="append", default=None, help="a pool campaign (repeatable)")
    p.add_argument("--repeats", default="highjump-pool-repeats")
    p.add_argument("--of", default="highjump-pool-2", help="the pool campaign whose take-offs the repeats retrain")
    a = p.parse_args()
    compute(a.db, a.pool or ["highjump-pool-2", "highjump-pool-3"])
    repeatability(a.podium, a.db, a.repeats, a.of, a.table)


if __name__ == "__main__":
    main()
