#!/usr/bin/env python3
"""The figures of tasks/jump/RESULTS.md for a jump campaign, read from its Podium database (read-only): per trial
its take-off parameters, the bar (box width) reached, success over the 20 evaluation jumps at the
starting bar and at the bar reached, its strategy feature and cluster, the nearest captured
technique when labelled, samples and wall time; then the distinct strategies per stage, counted
over all trials and over the trials that clear the starting bar in at least half their jumps.
Markdown on stdout.

Usage: tasks/jump/report.py DATABASE CAMPAIGN_NAME
"""
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from campaign_db import minutes, open_campaign  # noqa: E402


def main(db_path, campaign):
    db, stages = open_campaign(db_path, campaign)
    for stage_id, name, config in stages:
        stage = json.loads(config).get("stage", "explore")
        trials = db.execute("SELECT id, idx, state, error, params, strategy, result_info, started_at, finished_at FROM trials "
                            "WHERE stage_id = ? ORDER BY idx", (stage_id,)).fetchall()
        print(f"\n### stage `{name}` ({stage}), {len(trials)} trials\n")
        if stage == "pose_vae":
            for _, idx, state, error, _, _, info, started, finished in trials:
                info = json.loads(info or "{}")
                print(f"- `{name}/{idx}`: {state}, {minutes(started, finished):.1f} min, {info.get('poses')} poses, "
                      f"reconstruction RMSE {info.get('rmse_rad', float('nan')):.3f} rad" + (f", error: {error}" if error else ""))
            continue
        print("| trial | params | bar reached m | success at start bar (20) | success at bar reached (20) | feature | strategy | technique | samples | min |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        clears, strategies, clearing_strategies = 0, set(), set()
        for trial_id, idx, state, error, params, strategy, info, started, finished in trials:
            info = json.loads(info or "{}")
            feature = [v for (v,) in db.execute("SELECT value FROM features WHERE trial_id = ? ORDER BY idx", (trial_id,))]
            start = info.get("start_bar", {}).get("success_rate", float("nan"))
            final = info.get("final_bar", {}).get("success_rate", float("nan"))
            technique = info.get("nearest_technique", {}).get("name", "–")
            p = ", ".join(f"{k} {v:.2f}" for k, v in json.loads(params).items())
            print(f"| `{name}/{idx}` {state if state != 'done' else ''} | {p} | {info.get('z_reached_m', float('nan')):.2f} | {start:.2f} | "
                  f"{final:.2f} | {', '.join(f'{v:.3f}' for v in feature)} | {strategy if strategy is not None else '–'} | {technique} | "
                  f"{info.get('samples', '–')} | {minutes(started, finished):.1f} |" + (f" error: {error}" if error else ""))
            if strategy is not None:
                strategies.add(strategy)
                if start >= 0.5:
                    clearing_strategies.add(strategy)
            clears += start >= 0.5
        print(f"\n{clears} of {len(trials)} trials clear the starting bar in at least 10 of 20 jumps; distinct strategies: "
              f"{len(strategies)} over all trials, {len(clearing_strategies)} over those that clear it.")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(*sys.argv[1:])
