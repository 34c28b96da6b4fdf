#!/usr/bin/env python3
"""The figures of tasks/sprint/RESULTS.md for a sprint campaign, read through the `podium` command line
(`podium summary --json`, `podium export --format json --metrics`): per Start trial its final landing rate (over
all and per reference), tracking error and COM speed at the landing; per Accelerate trial its final runs (finish
rate, speed over the first and last segment, flight, rise) and the training distance's first and last tenth; the
dip stage's best candidate and its CMA-ES generations; the race's summary with its wind and dip checks; then the
task's quick bars (a)-(c) (docs/tasks/sprint.md), each against the trial that comes closest, the wall time and
samples per stage. Markdown on stdout.

Usage: tasks/sprint/report.py DATABASE CAMPAIGN (PODIUM=path/to/podium to choose the binary)
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from campaign_db import minutes, open_campaign, series, training_minutes, wall_time_line  # noqa: E402


def fmt(v, digits=3):
    return "-" if v is None else f"{v:.{digits}f}"


def start_trial(row, info):
    per = ", ".join(f"{name} {r['landings']}/{r['episodes']}" for name, r in info["per_reference"].items())
    print(f"  - final episodes: landing rate {info['landing_rate']:.2f} (per reference: {per}; lowest "
          f"{info['min_reference_landing_rate']:.2f}), tracking error {info['tracking_error_rad']:.3f} rad, COM speed at "
          f"the landing {info['com_speed_ratio']:.2f} of the reference's, {info['landings']} landing states; "
          f"{info['samples']} samples")
    return row["name"], info


def accelerate_trial(row, info):
    print(f"  - final runs: finish rate {info['finish_rate']:.2f}, distance {info['distance_m']:.1f} m, speed over the first / "
          f"last {info['segment_m']:.0f} m {fmt(info['first_speed_mps'], 2)} / {fmt(info['last_speed_mps'], 2)} m/s, flight in "
          f"every last-segment stride {info['flight_rate']:.2f}, rise distance {fmt(info['rise_distance_m'], 1)} m (rate "
          f"{info['rise_rate']:.2f}); {info['handovers']} dip snapshots; {info['samples']} samples")
    first, last = info["train_distance_first_tenth_m"], info["train_distance_last_tenth_m"]
    print(f"  - training episodes' distance, first / last tenth: {fmt(first, 2)} / {fmt(last, 2)} m; starts: "
          f"{info['starts']['source']} ({info['starts']['count']})")
    curve = series(row, "accelerate/distance_m")
    if curve:
        print("  - test distance (m) by samples: " + ", ".join(f"{s:.0f}: {v:.1f}" for s, v in curve[:: max(1, len(curve) // 8)]))
    return row["name"], info


def dip_stage(rows):
    done = [r for r in rows if r["result"]]
    if not done:
        return None
    best = max(done, key=lambda r: -r["result"]["dip"]["mean_time_s"])
    info = best["result"]
    print(f"  - {len(done)} candidates; best `{best['name']}`: d_dip "
          f"{best['params']['d_dip_m']:.2f} m, θ_dip {best['params']['theta_dip_deg']:.1f}°, gain over no dip on the search's "
          f"{info['episodes']} snapshots {info['gain_s']:.4f} s ({info['improved']} faster, {info['added_falls']} falls added)")
    return best


def race_trial(info):
    s = info
    print(f"  - {s['episodes']} DR episodes: finish rate {s['finish_rate']:.2f} ({s['outcomes']}), finish time mean "
          f"{fmt(s['mean_finish_time_s'])} s (sd {fmt(s['std_finish_time_s'])}), top speed {fmt(s['mean_top_speed_mps'], 2)} m/s, "
          f"steps {fmt(s['mean_steps'], 1)}, step length {fmt(s['mean_step_length_m'], 2)} m, frequency "
          f"{fmt(s['mean_step_frequency_hz'], 2)} Hz, rise {fmt(s['mean_rise_distance_m'], 1)} m, lean over the first segment "
          f"{fmt(s['mean_first_segment_lean_deg'], 1)}°")
    w = s.get("wind_check")
    if w:
        print(f"  - wind check (−2 vs +2 m/s, paired): {w['pairs']} pairs, headwind − tailwind {fmt(w['mean_difference_s'])} s, "
              f"headwind slower in {w['headwind_slower']}")
    d = s.get("dip_check")
    if d:
        print(f"  - dip check ({s['dip']['distance_m']:.2f} m, {s['dip']['angle_deg']:.1f}°; source {info.get('dip_source')}): "
              f"{d['pairs']} pairs, gain {fmt(d['mean_gain_s'], 4)} s ± {fmt(d['gain_standard_error_s'], 4)}, faster in "
              f"{d['improved']}, falls added {d['added_falls']}")


def bars(starts, accelerates, race):
    print("\n### the quick bars (docs/tasks/sprint.md)\n")
    print("| bar | closest trial | figure | met |\n|---|---|---|---|")
    if starts:
        name, i = max(starts, key=lambda s: (s[1]["min_reference_landing_rate"], s[1]["landing_rate"], -s[1]["tracking_error_rad"]))
        met = i["min_reference_landing_rate"] >= 0.8 and i["tracking_error_rad"] <= 0.3 and i["com_speed_ratio"] >= 0.7
        print(f"| (a) Start: every reference lands ≥ 80%, tracking ≤ 0.3 rad, COM speed ≥ 70% | `{name}` | lowest reference "
              f"{i['min_reference_landing_rate']:.2f}, {i['tracking_error_rad']:.3f} rad, {i['com_speed_ratio']:.2f} | {met} |")
    if accelerates:
        name, i = max(accelerates, key=lambda a: (a[1]["finish_rate"], a[1]["distance_m"]))
        first, last = i["first_speed_mps"], i["last_speed_mps"]
        ratio = last / first if first and last else None
        tenth = (i["train_distance_last_tenth_m"] / i["train_distance_first_tenth_m"]
                 if i["train_distance_first_tenth_m"] else None)
        met = (i["finish_rate"] >= 0.8 and ratio is not None and ratio >= 1.25 and last >= 2.5 and i["flight_rate"] >= 1.0
               and tenth is not None and tenth >= 3)
        print(f"| (b) stage 2: ≥ 80% over the track; last/first segment speed ≥ 1.25× and ≥ 2.5 m/s; flight in every last-"
              f"segment stride; training distance last/first tenth ≥ 3× | `{name}` | finish {i['finish_rate']:.2f}; "
              f"{fmt(ratio, 2)}×, {fmt(last, 2)} m/s; flight {i['flight_rate']:.2f}; {fmt(tenth, 2)}× | {met} |")
    if race and race.get("dip_check"):
        d = race["dip_check"]
        gain = d["mean_gain_s"]
        met = gain is not None and gain >= 0.02 and d["improved"] >= 15 and d["added_falls"] == 0
        print(f"| (c) dip ≥ 0.02 s faster paired, ≥ 15 of 20 faster, no fall added (race's held-out episodes) | race | "
              f"{fmt(gain, 4)} s, {d['improved']} of {d['pairs']} faster, {d['added_falls']} falls added | {met} |")


def main(db_path, campaign):
    summary, rows = open_campaign(db_path, campaign)
    starts, accelerates, race, spans = [], [], None, []
    for stage_summary in summary["stages"]:
        name = stage_summary["name"]
        stage = stage_summary["config"].get("stage", "start")
        stage_rows = rows[name]
        begun = [r["started_at"] for r in stage_rows if r["started_at"]]
        ended = [r["finished_at"] for r in stage_rows if r["finished_at"]]
        wall = minutes(min(begun), max(ended)) if begun and ended and len(ended) == len(stage_rows) else float("nan")
        print(f"\n### stage `{name}` ({stage}): {len(stage_rows)} trials, {wall:.1f} min\n")
        spans += [(r["started_at"], r["finished_at"]) for r in stage_rows]
        if stage == "dip":
            dip_stage(stage_rows)
            continue
        for row in stage_rows:
            info, error = row["result"], row["error"]
            print(f"- `{row['name']}` (trial seed {row['seed']}): {row['state']}, "
                  f"{minutes(row['started_at'], row['finished_at']):.1f} min" + (f", error: {error}" if error else ""))
            if not info:
                continue
            if stage == "start":
                starts.append(start_trial(row, info))
            elif stage == "accelerate":
                accelerates.append(accelerate_trial(row, info))
            elif stage == "race":
                race = info
                race_trial(info)
            at = training_minutes(row)
            if at:
                print(f"  - {max(at.values()):.1f} min of training (time/* metrics)")
    bars(starts, accelerates, race)
    if spans:
        print("\n" + wall_time_line(spans))


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
