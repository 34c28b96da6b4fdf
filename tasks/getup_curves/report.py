#!/usr/bin/env python3
"""The figures of tasks/getup_curves/RESULTS.md for a style-curve get-up campaign, read through the `podium` command line
(`podium summary --json`, `podium export --format json --metrics`): per pose_cvae trial its poses, reconstruction
errors and PCA check; per train trial its final test on flat, per curve
(success, the tracking errors of the successful episodes over [0, T], the rise time), the average return rate's first
and last tenth, whether the easy region opened and when, the training's length and speed; per edit trial its edit and
figures; then the task's quick bars (a)-(d) (docs/tasks/getup_curves.md), each against the trial that comes closest, and
the campaign's wall time. Markdown on stdout.

Usage: tasks/getup_curves/report.py DATABASE CAMPAIGN (PODIUM=path/to/podium to choose the binary)
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from campaign_db import minutes, open_campaign, series, training_minutes, wall_time_line  # noqa: E402


def fmt(v, digits=3):
    return "-" if v is None else f"{v:.{digits}f}"


def tenths(values):
    """(mean of the first tenth, mean of the last tenth) of a curve."""
    if not values:
        return None, None
    n = max(1, len(values) // 10)
    return sum(values[:n]) / n, sum(values[-n:]) / n


def train_trial(row, info):
    print(f"  - {info['env_steps']} control steps (ended by {info['stopped_by']}); final test on flat: success "
          f"{info['success_rate']:.2f}, mean r_task {info['mean_r_task']:.3f}, average return rate {info['average_return_rate']:.3f}")
    print("\n  | curve | success | h error m | angle error ° | rise time s (risen) |\n  |---|---|---|---|---|")
    for f in info["following"]:
        print(f"  | {f['curve']} | {f['success_rate']:.2f} | {fmt(f['h_error_m'])} | {fmt(f['angle_error_deg'], 1)} | "
              f"{fmt(f['rise_time_s'], 2)} ({f['risen']}) |")
    rate = [v for _, v in series(row, "test/average_return_rate")]
    first, last = tenths(rate)
    print(f"\n  - average return rate over {len(rate)} tests, first / last tenth: {fmt(first)} / {fmt(last)}")
    opened = series(row, "curriculum/open_levels")
    print(f"  - regions open at the end: {info.get('open_levels', 1)}"
          + (f" (opened at control steps {', '.join(f'{s:.0f}' for s, _ in opened)})" if opened else " (easy never opened)"))
    at = training_minutes(row)
    if len(at) > 1:
        steps = sorted(at)
        print(f"  - {steps[-1] / (at[steps[-1]] * 60):.0f} control steps/s over {at[steps[-1]]:.1f} min of training (time/* metrics)")
    return row["name"], info, (first, last)


def cvae_trial(info):
    print(f"  - {info['train_poses']} training and {info['heldout_poses']} held-out poses; reconstruction RMSE "
          f"{info['train_rmse_rad']:.3f} / {info['heldout_rmse_rad']:.3f} rad (training / held out) against the mean "
          f"pose's {info['mean_pose_rmse_rad']:.3f}; {info['pca_components_85']} principal components cover 85%")


def edit_trials(rows):
    done = [r for r in rows if r["result"]]
    print(f"  - {len(done)} edits, {len({r['strategy'] for r in done if r['strategy'] is not None})} distinct styles")
    print("\n  | trial | rise fraction | h offset m | T scale | success | h error m | rise time s |\n  |---|---|---|---|---|---|---|")
    for r in done:
        p, i = r["params"], r["result"]
        print(f"  | `{r['name']}` | {p['rise_fraction']:.2f} | {p['h_offset_m']:+.2f} | {p['duration_scale']:.2f} | "
              f"{i['success_rate']:.2f} | {fmt(i['h_error_m'])} | {fmt(i['rise_time_s'], 2)} |")


def bars(trains):
    print("\n### the quick bars (docs/tasks/getup_curves.md)\n")
    print("| bar | closest trial | figure | met |\n|---|---|---|---|")
    if not trains:
        return
    name, info, _ = max(trains, key=lambda t: min(f["success_rate"] for f in t[1]["following"]))
    low = min(f["success_rate"] for f in info["following"])
    print(f"| (a) success ≥ 50% on every curve | `{name}` | lowest {low:.2f} | {low >= 0.5} |")
    errors = [(f["h_error_m"], f["angle_error_deg"]) for f in info["following"] if f["h_error_m"] is not None]
    if errors:
        h, a = max(e[0] for e in errors), max(e[1] for e in errors)
        print(f"| (b) on successes, mean h error ≤ 0.15 m and angle error ≤ 25° | `{name}` | worst curve {h:.3f} m, {a:.1f}° | "
              f"{h <= 0.15 and a <= 25} |")
    else:
        print(f"| (b) on successes, mean h error ≤ 0.15 m and angle error ≤ 25° | `{name}` | no successful episode | False |")
    name, _, (first, last) = max(trains, key=lambda t: (t[2][1] or 0) / (t[2][0] or 1e-9))
    ratio = last / first if first else None
    print(f"| (c) average return rate, last tenth ≥ 2× first | `{name}` | {fmt(first)} → {fmt(last)} ({fmt(ratio, 2)}×) | "
          f"{ratio is not None and ratio >= 2} |")
    for name, info, _ in trains:
        rise = {f["curve"]: f["rise_time_s"] for f in info["following"]}
        if all(k in rise for k in ("faceup_early", "faceup", "faceup_late")):
            e, b, l = rise["faceup_early"], rise["faceup"], rise["faceup_late"]
            met = None not in (e, b, l) and b - e >= 0.25 and l - b >= 0.25
            print(f"| (d) rise early < base < late, gaps ≥ 0.25 s | `{name}` | {fmt(e, 2)} / {fmt(b, 2)} / {fmt(l, 2)} s | {met} |")


def main(db_path, campaign):
    summary, rows = open_campaign(db_path, campaign)
    trains, spans = [], []
    for stage_summary in summary["stages"]:
        name = stage_summary["name"]
        stage = stage_summary["config"].get("stage", "train")
        print(f"\n### stage `{name}` ({stage})\n")
        spans += [(r["started_at"], r["finished_at"]) for r in rows[name]]
        if stage == "edit":
            edit_trials(rows[name])
            continue
        for row in rows[name]:
            info, error = row["result"], row["error"]
            print(f"- `{row['name']}` (trial seed {row['seed']}): {row['state']}, "
                  f"{minutes(row['started_at'], row['finished_at']):.1f} min" + (f", error: {error}" if error else ""))
            if info and stage == "train":
                trains.append(train_trial(row, info))
            elif info and stage == "pose_cvae":
                cvae_trial(info)
    bars(trains)
    if spans:
        print("\n" + wall_time_line(spans))


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
