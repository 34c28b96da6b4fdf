#!/usr/bin/env python3
"""The figures of tasks/getup/RESULTS.md for a get-up campaign, read through the `podium` command line
(`podium summary --json`, `podium export --format json --metrics`): per Weaker trial the curriculum, the
exported policy's test, the head-height curve's first and last tenth, the wall time, and from its time/*
metrics the minutes to the first get-up and the environment steps per second; per Slower and Evaluate
trial their results; then the task's four bars (RESULTS.md), each against the trial that comes closest,
and the campaign's wall time. Markdown on stdout.

Usage: tasks/getup/report.py DATABASE CAMPAIGN (PODIUM=path/to/podium to choose the binary)
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from campaign_db import minutes, open_campaign, series, training_minutes, wall_time_line  # noqa: E402


def curve_table(row, every=100_000):
    """The learning curves every `every` environment steps, as a Markdown table."""
    names = ["test_return", "head_height_m", "success_rate", "risen_rate", "stood_rate", "risen_on_back_rate", "stood_on_back_rate",
             "head_drops", "curriculum/strength", "sac/alpha"]
    by_step = {name: dict(series(row, name)) for name in names}
    steps = sorted(s for s in by_step["test_return"] if s % every == 0)
    print("\n  | env steps | " + " | ".join(names) + " |\n  |---|" + "---|" * len(names))
    for step in steps:
        print(f"  | {step:.0f} | " + " | ".join(f"{by_step[n].get(step, float('nan')):.4g}" for n in names) + " |")
    print()


def head_curve(heads):
    """(mean of the first tenth, mean of the last tenth) of a head-height curve: bar (c)'s two ends."""
    tenth = max(1, len(heads) // 10)
    return sum(heads[:tenth]) / tenth, sum(heads[-tenth:]) / tenth


def bars(weaker, evaluate, spans):
    """The task's `quick` bars (RESULTS.md), each against the done trial that reaches it best: `weaker` holds (trial, result info,
    head-curve gain in m), `evaluate` (trial, {speed name: its result}), `spans` every trial's (start, finish)."""
    print("\n### the quick bars (RESULTS.md)\n")
    print("| bar | closest trial | figure | met |\n|---|---|---|---|")
    if weaker:
        name, info, _ = max(weaker, key=lambda w: (w[1]["success_rate"], w[1]["levels"]))
        print(f"| (a) ≥ 8/10 fixed starts up at the final strength | `{name}` | {info['success_rate'] * 10:.0f}/10 at β "
              f"{info['policy_strength']:.4f} | {info['success_rate'] >= 0.8} |")
        name, info, _ = max(weaker, key=lambda w: (w[1]["levels"], w[1]["success_rate"]))
        print(f"| (b) ≥ 3 advances (β ≤ 0.857) | `{name}` | {info['levels']} advances, β {info['final_strength']:.4f} | "
              f"{info['levels'] >= 3} |")
        name, _, gain = max(weaker, key=lambda w: w[2])
        print(f"| (c) head curve, last tenth − first ≥ +0.8 m | `{name}` | {gain:+.3f} m | {gain >= 0.8} |")
    for name, speeds in evaluate:
        fast, slow, half = speeds.get("fast"), speeds.get("k0.25"), speeds.get("k0.5")
        row = f"| (d) COM error < 0.15 m at κ 0.5; rise at κ 0.25 ≥ 3× fast | `{name}` | "
        if not (fast and slow and half):
            print(row + f"not measured: it evaluated {', '.join(speeds)} | False |")
            continue
        ratio = slow["rise_time_s"] / fast["rise_time_s"] if slow["risen"] and fast["risen"] else float("nan")
        print(row + f"{half['com_error_m']:.3f} m; {slow['rise_time_s']:.2f} s / {fast['rise_time_s']:.2f} s = {ratio:.2f}× "
              f"({slow['risen']} and {fast['risen']} risers) | {half['com_error_m'] < 0.15 and ratio >= 3} |")
    if spans:
        print("\n" + wall_time_line(spans))


def weaker_trial(name, row, info):
    """A done Weaker trial's lines; returns its (name, info, head-curve gain) for the bars."""
    heads = [v for _, v in series(row, "head_height_m")]
    first, last = head_curve(heads) if heads else (float("nan"), float("nan"))
    print(f"  - environment steps {info['env_steps']} (ended by {info.get('stopped_by', 'steps')}), curriculum advances {info['levels']}, "
          f"final strength {info['final_strength']:.4f}; exported policy passed at β = {info['policy_strength']:.4f}"
          f" (passed any test: {info['passed']}): success {info['success_rate']:.2f} over the fixed starts, "
          f"test return {info['test_return']:.1f}")
    print(f"  - head height (m), mean of the first and last tenth of {len(heads)} tests: {first:.3f} → {last:.3f} "
          f"(+{last - first:.3f}); best test: {max(heads, default=float('nan')):.3f}")
    best = max(series(row, "test_return") or [(0, 0)], key=lambda p: p[1])
    first_up = next((s for s, v in series(row, "success_rate") if v > 0), None)
    at = training_minutes(row)
    when = f" ({at[first_up]:.1f} min of training)" if first_up in at else ""
    print(f"  - best test return {best[1]:.1f} at step {best[0]:.0f}; first success > 0 at step "
          + (f"{first_up:.0f}{when}" if first_up is not None else "never"))
    if len(at) > 1:
        # A warm-started trial's series begins at its source's steps: count from the first round's start.
        steps = sorted(at)
        trained = steps[-1] - steps[0] + (steps[1] - steps[0])
        print(f"  - {trained / (at[steps[-1]] * 60):.0f} environment steps/s over {trained:.0f} steps and "
              f"{at[steps[-1]]:.1f} min of training (time/* metrics)")
    print(f"  - strategy features {', '.join(f'{k} {v:.3f}' for k, v in row['features'].items())}")
    return name, info, last - first


def main(db_path, campaign):
    summary, rows = open_campaign(db_path, campaign)
    weaker, evaluate, spans = [], [], []  # for the bars
    for stage_summary in summary["stages"]:
        name = stage_summary["name"]
        stage = stage_summary["config"].get("stage", "weaker")
        print(f"\n### stage `{name}` ({stage})\n")
        for row in rows[name]:
            info, state, error = row["result"], row["state"], row["error"]
            spans.append((row["started_at"], row["finished_at"]))
            print(f"- `{row['name']}` (trial seed {row['seed']}): {state}, {minutes(row['started_at'], row['finished_at']):.1f} min"
                  + (f", error: {error}" if error else ""))
            if not info:  # running or failed: its curves so far
                if stage == "weaker":
                    curve_table(row)
                continue
            if stage == "weaker":
                weaker.append(weaker_trial(row["name"], row, info))
                curve_table(row)
            elif stage == "slower":
                print(f"  - environment steps {info['env_steps']} (ended by {info.get('stopped_by', 'steps')}), last test at κ = 0.5: success {info['success_rate']:.2f}, "
                      f"COM error {info['com_error_m']:.3f} m, return {info['test_return']:.1f}; π_weak's β {info['weak_strength']:.4f}")
            else:
                evaluate.append((row["name"], {s["name"]: s for s in info["speeds"]}))
                for s in info["speeds"]:
                    print(f"  - {s['name']:>8}: success {s['success_rate']:.2f}, risen {s['risen']}, stood {s.get('stood', float('nan'))}, rise time {s['rise_time_s']:.2f} s, "
                          f"head drops {s.get('drops', float('nan')):.2f}, peak head top {s.get('peak_head_m', float('nan')):.2f} m, "
                          f"COM error {s['com_error_m']:.3f} m, τ_fast {s['fast_rise_time_s']:.2f} s")
                print(f"  - strategy features {', '.join(f'{k} {v:.3f}' for k, v in row['features'].items())}")
    bars(weaker, evaluate, spans)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
