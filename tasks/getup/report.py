#!/usr/bin/env python3
"""The figures of tasks/getup/RESULTS.md for a get-up campaign, read from its Podium database (read-only):
per Weaker trial the curriculum, the exported policy's test, the head-height curve's first and
last tenth, the wall time, and from its trial.log the minutes to the first get-up and the
environment steps per second; per Slower and Evaluate trial their results; then the task's four
bars (RESULTS.md), each against the trial that comes closest, and the campaign's wall time. Markdown on stdout.

Usage: tasks/getup/report.py DATABASE CAMPAIGN_NAME
"""
import json
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from campaign_db import minutes, open_campaign, trial_log  # noqa: E402


def curve_table(series, every=100_000):
    """The learning curves every `every` environment steps, as a Markdown table."""
    names = ["test_return", "head_height_m", "success_rate", "risen_rate", "stood_rate", "risen_on_back_rate", "stood_on_back_rate",
             "head_drops", "curriculum/strength", "sac/alpha"]
    by_step = {name: dict(series.get(name, [])) for name in names}
    steps = sorted(s for s in by_step["test_return"] if s % every == 0)
    print("\n  | env steps | " + " | ".join(names) + " |\n  |---|" + "---|" * len(names))
    for step in steps:
        print(f"  | {step:.0f} | " + " | ".join(f"{by_step[n].get(step, float('nan')):.4g}" for n in names) + " |")
    print()


def head_curve(heads):
    """(mean of the first tenth, mean of the last tenth) of a head-height curve: bar (c)'s two ends."""
    tenth = max(1, len(heads) // 10)
    return sum(heads[:tenth]) / tenth, sum(heads[-tenth:]) / tenth


def training_minutes(log_path):
    """{environment step: minutes of training so far} from Weaker's per-test log lines (rollouts + updates + test
    seconds, summed over every attempt's lines); empty without a log."""
    line = re.compile(r"getup: step (\d+): .*\(([\d.]+) s\), updates ([\d.]+) s .*test ([\d.]+) s")
    spent, at = 0.0, {}
    try:
        for m in filter(None, map(line.search, open(log_path, encoding="utf-8", errors="replace"))):
            spent += sum(float(m[i]) for i in (2, 3, 4))
            at.setdefault(int(m[1]), spent / 60)
    except FileNotFoundError:
        pass
    return at


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
    if spans and all(finished for _, finished in spans):
        start, end = min(s for s, _ in spans), max(f for _, f in spans)
        print(f"\ncampaign wall time: {minutes(start, end):.1f} min (first trial start to last trial end)")
    elif spans:
        print("\ncampaign wall time: not yet (trials still queued or running)")


def main(db_path, campaign):
    db, stages = open_campaign(db_path, campaign)
    weaker, evaluate, spans = [], [], []  # for the bars
    for stage_id, name, config in stages:
        stage = json.loads(config).get("stage", "weaker")
        print(f"\n### stage `{name}` ({stage})\n")
        trials = db.execute("SELECT id, idx, seed, state, error, result_info, started_at, finished_at FROM trials "
                            "WHERE stage_id = ? ORDER BY idx", (stage_id,)).fetchall()
        for trial_id, idx, seed, state, error, info, started, finished in trials:
            spans.append((started, finished))
            print(f"- `{name}/{idx}` (trial seed {seed & 0xFFFFFFFFFFFFFFFF}): {state}, {minutes(started, finished):.1f} min" + (f", error: {error}" if error else ""))
            series = {}
            for metric, step, value in db.execute("SELECT name, step, value FROM metrics WHERE trial_id = ? ORDER BY step",
                                                  (trial_id,)):
                series.setdefault(metric, []).append((step, value))
            if not info:  # running or failed: its curves so far
                if stage == "weaker":
                    curve_table(series)
                continue
            info = json.loads(info)
            if stage == "weaker":
                heads = [v for _, v in series.get("head_height_m", [])]
                first, last = head_curve(heads)
                weaker.append((f"{name}/{idx}", info, last - first))
                print(f"  - environment steps {info['env_steps']} (ended by {info.get('stopped_by', 'steps')}), curriculum advances {info['levels']}, "
                      f"final strength {info['final_strength']:.4f}; exported policy passed at β = {info['policy_strength']:.4f}"
                      f" (passed any test: {info['passed']}): success {info['success_rate']:.2f} over the fixed starts, "
                      f"test return {info['test_return']:.1f}")
                print(f"  - head height (m), mean of the first and last tenth of {len(heads)} tests: {first:.3f} → {last:.3f} "
                      f"(+{last - first:.3f}); best test: {max(heads):.3f}")
                best = max(series.get("test_return", [(0, 0)]), key=lambda p: p[1])
                first_up = next((s for s, v in series.get("success_rate", []) if v > 0), None)
                at = training_minutes(trial_log(db_path, db, stage_id, idx))
                when = f" ({at[first_up]:.1f} min of training)" if first_up in at else ""
                print(f"  - best test return {best[1]:.1f} at step {best[0]:.0f}; first success > 0 at step "
                      + (f"{first_up:.0f}{when}" if first_up is not None else "never"))
                if len(at) > 1:
                    # A warm-started trial's log begins at its source's steps: count from the first round's start.
                    steps = sorted(at)
                    trained = steps[-1] - steps[0] + (steps[1] - steps[0])
                    print(f"  - {trained / (at[steps[-1]] * 60):.0f} environment steps/s over {trained} steps and "
                          f"{at[steps[-1]]:.1f} min of training (trial.log)")
                print(f"  - strategy features {[round(x, 3) for x in info.get('features', [])]}")
            if stage == "weaker":
                curve_table(series)
            elif stage == "slower":
                print(f"  - environment steps {info['env_steps']} (ended by {info.get('stopped_by', 'steps')}), last test at κ = 0.5: success {info['success_rate']:.2f}, "
                      f"COM error {info['com_error_m']:.3f} m, return {info['test_return']:.1f}; π_weak's β {info['weak_strength']:.4f}")
            else:
                evaluate.append((f"{name}/{idx}", {s["name"]: s for s in info["speeds"]}))
                for s in info["speeds"]:
                    print(f"  - {s['name']:>8}: success {s['success_rate']:.2f}, risen {s['risen']}, stood {s.get('stood', float('nan'))}, rise time {s['rise_time_s']:.2f} s, "
                          f"head drops {s.get('drops', float('nan')):.2f}, peak head top {s.get('peak_head_m', float('nan')):.2f} m, "
                          f"COM error {s['com_error_m']:.3f} m, τ_fast {s['fast_rise_time_s']:.2f} s")
                print(f"  - strategy features {[round(x, 3) for x in info['features']]}")
    bars(weaker, evaluate, spans)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
