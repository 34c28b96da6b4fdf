#!/usr/bin/env python3
"""The figures of tasks/jump/RESULTS.md for a jump campaign, read through the `podium` command line
(`podium summary --json`, `podium export --format json --metrics`): per trial its take-off parameters, the
bar (box width) reached, success over the 20 evaluation jumps at the starting bar and at the bar reached,
its strategy feature and cluster, the nearest captured technique when labelled, samples and wall time, the
training's minutes from its time/* metrics; then the distinct strategies per stage, counted over all trials
and over the trials that clear the starting bar in at least half their jumps. Markdown on stdout.

Usage: tasks/jump/report.py DATABASE CAMPAIGN (PODIUM=path/to/podium to choose the binary)
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from campaign_db import minutes, open_campaign, training_minutes  # noqa: E402


def trained_minutes(row):
    """Minutes of training (rollouts, updates, tests) from the time/* metrics; "–" without them."""
    at = training_minutes(row)
    return f"{at[max(at)]:.1f}" if at else "–"


def main(db_path, campaign):
    summary, rows = open_campaign(db_path, campaign)
    for stage_summary in summary["stages"]:
        name = stage_summary["name"]
        stage = stage_summary["config"].get("stage", "explore")
        trials = rows[name]
        print(f"\n### stage `{name}` ({stage}), {len(trials)} trials\n")
        if stage == "pose_vae":
            for row in trials:
                info, error = row["result"] or {}, row["error"]
                print(f"- `{row['name']}`: {row['state']}, {minutes(row['started_at'], row['finished_at']):.1f} min, {info.get('poses')} poses, "
                      f"reconstruction RMSE {info.get('rmse_rad', float('nan')):.3f} rad" + (f", error: {error}" if error else ""))
            continue
        print("| trial | params | bar reached m | success at start bar (20) | success at bar reached (20) | feature | strategy | technique | samples | min | training min |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        clears, strategies, clearing_strategies = 0, set(), set()
        for row in trials:
            info, state, error, strategy = row["result"] or {}, row["state"], row["error"], row["strategy_label"]
            start = info.get("start_bar", {}).get("success_rate", float("nan"))
            final = info.get("final_bar", {}).get("success_rate", float("nan"))
            technique = info.get("nearest_technique", {}).get("name", "–")
            p = ", ".join(f"{k} {v:.2f}" for k, v in row["params"].items())
            feature = ", ".join(f"{k} {v:.3f}" for k, v in row["features"].items())
            print(f"| `{row['name']}` {state if state != 'done' else ''} | {p} | {info.get('z_reached_m', float('nan')):.2f} | {start:.2f} | "
                  f"{final:.2f} | {feature} | {strategy if strategy is not None else '–'} | {technique} | "
                  f"{info.get('samples', '–')} | {minutes(row['started_at'], row['finished_at']):.1f} | {trained_minutes(row)} |"
                  + (f" error: {error}" if error else ""))
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
