#!/usr/bin/env python3
"""The tasks' reports (tasks/getup/report.py, tasks/jump/report.py, tasks/sprint/report.py,
tasks/getup_curves/report.py) on small campaigns the test runs: campaigns/getup.json,
campaigns/highjump.json, campaigns/sprint.json and campaigns/getup_curves.json at the smoke preset,
cut to one Weaker trial, two explore samples, one CMA-ES generation and four edits. Each report
must name every stage and print the figures `podium export` holds.

Usage: reports_test.py PODIUM_BINARY SOURCE_DIR
"""
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print(f"FAILED: {what}", file=sys.stderr)


def podium(binary, cwd, *args):
    done = subprocess.run([binary, *args], cwd=cwd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"podium {' '.join(args)} exited {done.returncode}: {done.stderr}")
    return done.stdout


def smoke_spec(source, name, cut):
    spec = json.loads((source / "campaigns" / name).read_text())
    for stage in spec["stages"]:
        stage["preset"] = "smoke"
    spec["trial_timeout_s"] = 300
    spec["retries"] = 0
    cut(spec["stages"])
    return spec


def report(source, script, db, campaign, env):
    done = subprocess.run([sys.executable, str(source / "tasks" / script), str(db), campaign], capture_output=True,
                          text=True, env=env)
    check(done.returncode == 0, f"{script} exited {done.returncode}: {done.stderr}")
    return done.stdout


def main(binary, source):
    binary, source = str(Path(binary).resolve()), Path(source).resolve()
    env = dict(os.environ, PODIUM=binary)
    with tempfile.TemporaryDirectory(prefix="podium-reports-") as tmp:
        tmp = Path(tmp)

        def cut_getup(stages):
            stages[0]["budget"]["trials"] = 1

        def cut_jump(stages):
            stages[1]["budget"]["trials"] = 2
            stages[2]["search"]["config"]["trials_per_input"] = 1
            stages[2]["budget"]["trials"]["per_input"] = 1
            # No smoke jump clears its bar, so none is a strategy: hand over the best explore trial.
            stages[2]["inputs"].update(select="top", k=1)

        def cut_sprint(stages):
            stages[1]["config"].pop("primitive_clips")  # off at smoke; its paths are relative to the campaign file
            stages[2]["budget"]["trials"] = 6  # one generation of λ = 6

        def cut_curves(stages):
            # The pose clips' paths are relative to the campaign file; the spec is written elsewhere.
            for clip in stages[0]["config"]["pose_clips"]:
                for key in ("clip", "character"):
                    clip[key] = str((source / "campaigns" / clip[key]).resolve())
            stages[1]["budget"]["trials"] = 1
            stages[1]["config"]["curves"] = ["faceup", "facedown", "faceup_early", "faceup_late"]
            stages[2]["budget"]["trials"] = 4

        for name, cut in (("getup.json", cut_getup), ("highjump.json", cut_jump), ("sprint.json", cut_sprint),
                          ("getup_curves.json", cut_curves)):
            (tmp / name).write_text(json.dumps(smoke_spec(source, name, cut)))
            podium(binary, tmp, "submit", name)
        podium(binary, tmp, "run", "--workers", "2")
        db = tmp / "podium.db"

        rows = json.loads(podium(binary, tmp, "export", "getup", "--format", "json"))
        text = report(source, "getup/report.py", db, "getup", env)
        for stage in ("weaker", "slower", "evaluate"):
            check(f"### stage `{stage}` ({stage})" in text, f"getup report names stage {stage}")
        for row in rows:
            check(f"- `{row['name']}` (trial seed {row['seed']}): done" in text, f"getup report lists {row['name']}")
        weaker = next(r for r in rows if r["stage"] == "weaker")
        check(f"success {weaker['result']['success_rate']:.2f} over the fixed starts" in text, "getup report: Weaker's success")
        check("environment steps/s over" in text and "(time/* metrics)" in text, "getup report: the training's speed from time/*")
        evaluate = next(r for r in rows if r["stage"] == "evaluate")
        fast = next(s for s in evaluate["result"]["speeds"] if s["name"] == "fast")
        check(f"    fast: success {fast['success_rate']:.2f}, risen {fast['risen']}" in text, "getup report: Evaluate's fast speed")
        check("### the quick bars (RESULTS.md)" in text and "campaign wall time:" in text, "getup report: the bars")

        rows = json.loads(podium(binary, tmp, "export", "highjump", "--format", "json"))
        text = report(source, "jump/report.py", db, "highjump", env)
        for stage in ("pose_vae", "explore", "novel"):
            check(f"### stage `{stage}` ({stage})" in text, f"jump report names stage {stage}")
        for row in (r for r in rows if r["stage"] == "explore"):
            feature = f"up_angle_rad {row['features']['up_angle_rad']:.3f}"
            line = next((l for l in text.splitlines() if l.startswith(f"| `{row['name']}`")), "")
            check(f"| {row['result']['z_reached_m']:.2f} |" in line and feature in line, f"jump report: {row['name']}'s figures")
        explore = {r["strategy"] for r in rows if r["stage"] == "explore" and r["strategy"] is not None}
        check(f"distinct strategies: {len(explore)} over all trials" in text, "jump report: explore's strategies")
        rows = json.loads(podium(binary, tmp, "export", "sprint", "--format", "json"))
        text = report(source, "sprint/report.py", db, "sprint", env)
        for stage in ("start", "accelerate", "dip", "race"):
            check(f"### stage `{stage}` ({stage})" in text, f"sprint report names stage {stage}")
        for row in (r for r in rows if r["stage"] == "start"):
            check(f"landing rate {row['result']['landing_rate']:.2f} (per reference:" in text, f"sprint report: {row['name']}")
        race = next(r for r in rows if r["stage"] == "race")
        check(f"{race['result']['episodes']} DR episodes: finish rate {race['result']['finish_rate']:.2f}" in text,
              "sprint report: the race")
        check("dip check (" in text and "### the quick bars" in text, "sprint report: the dip check and the bars")

        rows = json.loads(podium(binary, tmp, "export", "getup_curves", "--format", "json"))
        text = report(source, "getup_curves/report.py", db, "getup_curves", env)
        for stage in ("pose_cvae", "train", "edit"):
            check(f"### stage `{stage}` ({stage})" in text, f"getup_curves report names stage {stage}")
        cvae = next(r for r in rows if r["stage"] == "pose_cvae")["result"]
        check(f"{cvae['train_poses']} training and {cvae['heldout_poses']} held-out poses" in text, "getup_curves report: the C-VAE")
        train = next(r for r in rows if r["stage"] == "train")
        for f in train["result"]["following"]:
            check(f"  | {f['curve']} | {f['success_rate']:.2f} |" in text, f"getup_curves report: curve {f['curve']}")
        check(f"  - {len([r for r in rows if r['stage'] == 'edit'])} edits," in text, "getup_curves report: the edits")
        check("| (d) rise early < base < late" in text, "getup_curves report: the bars")
    if failures:
        sys.exit(f"{len(failures)} checks failed")
    print("reports_test: ok")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(*sys.argv[1:])
