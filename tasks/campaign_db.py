"""Shared by the tasks' report.py scripts: a campaign as the `podium` command line gives it (`podium summary --json`
and `podium export --format json --metrics`), never its database schema or its logs."""
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path


def podium_binary():
    """The `podium` to ask: $PODIUM, else the repository's build/bin/podium, else the one on PATH."""
    if os.environ.get("PODIUM"):
        return os.environ["PODIUM"]
    built = Path(__file__).resolve().parent.parent / "build" / "bin" / "podium"
    if built.is_file():
        return str(built)
    found = shutil.which("podium")
    if not found:
        sys.exit("report.py: no podium binary (set PODIUM, build the repository, or put podium on PATH)")
    return found


def podium_json(db_path, *args):
    """`podium ARGS --db DB_PATH` parsed as JSON; exits with podium's own one-line error when it fails."""
    done = subprocess.run([podium_binary(), *args, "--db", str(db_path)], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"report.py: {done.stderr.strip() or f'podium {args[0]} exited {done.returncode}'}")
    return json.loads(done.stdout)


def open_campaign(db_path, campaign):
    """(summary, {stage name: [trial rows]}) of campaign `campaign` (an id or a name: the newest of that name):
    the summary as `podium summary --json` gives it (stages in order, each with its config), the rows as
    `podium export --format json --metrics` gives them (objectives and features named, metric series, result info)."""
    summary = podium_json(db_path, "summary", str(campaign), "--json")
    rows = podium_json(db_path, "export", str(summary["campaign"]["id"]), "--format", "json", "--metrics")
    by_stage = {stage["name"]: [] for stage in summary["stages"]}
    for row in rows:
        by_stage.setdefault(row["stage"], []).append(row)
    return summary, by_stage


def minutes(started, finished):
    """A trial's wall time in minutes from its stored start and finish (NaN while either is missing)."""
    return (finished - started) / 60 if finished and started else float("nan")


def series(row, name):
    """A trial's metric `name` as [(step, value)] in step order (empty when it has none)."""
    return sorted((step, value) for step, value in row.get("metrics", {}).get(name, []))


def training_minutes(row):
    """{environment step: minutes of training so far} from the training-stage driver's time/* metrics (rollouts,
    updates and the test at each test step, summed from the first); empty without them."""
    parts = [dict(series(row, f"time/{name}_s")) for name in ("rollout", "update", "test")]
    spent, at = 0.0, {}
    for step in sorted(parts[0]):
        spent += sum(p.get(step, 0.0) for p in parts)
        at[step] = spent / 60
    return at


def wall_time_line(spans):
    """The campaign's wall time from its trials' (started, finished) spans: first start to last end, or "not yet"
    while any trial is unfinished; "" without trials."""
    if spans and all(finished for _, finished in spans):
        start, end = min(s for s, _ in spans), max(f for _, f in spans)
        return f"campaign wall time: {minutes(start, end):.1f} min (first trial start to last trial end)"
    return "campaign wall time: not yet (trials still queued or running)" if spans else ""
