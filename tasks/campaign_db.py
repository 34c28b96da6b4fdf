"""Shared by the tasks' report.py scripts: a campaign's stages, read-only from its Podium database, trial wall times
and trial logs."""
import os
import re
import sqlite3
import sys


def open_campaign(db_path, campaign):
    """(connection, [(stage id, stage name, task config JSON)]) of the newest campaign named `campaign`;
    exits with a one-line error when there is none."""
    try:
        db = sqlite3.connect(f"file:{db_path}?mode=ro", uri=True)
        row = db.execute("SELECT id FROM campaigns WHERE name = ? ORDER BY id DESC", (campaign,)).fetchone()
    except sqlite3.Error as e:
        sys.exit(f"report.py: {db_path}: not a Podium database ({e})")
    if row is None:
        sys.exit(f"report.py: {db_path}: no campaign named {campaign!r}")
    stages = db.execute("SELECT id, name, task_config FROM stages WHERE campaign_id = ? ORDER BY idx", (row[0],)).fetchall()
    return db, stages


def minutes(started, finished):
    """A trial's wall time in minutes from its stored start and finish (NaN while either is missing)."""
    return (finished - started) / 60 if finished and started else float("nan")


def trial_log(db_path, db, stage_id, trial_index):
    """The path of a trial's trial.log, by store/run_folders.h's rule (`podium log CAMPAIGN TRIAL --path` prints
    the same): <run folder>/stage-<i>-<name>/trial-<n>/trial.log."""
    campaign, run_dir, stage_index, stage_name = db.execute(
        "SELECT c.id, c.run_dir, s.idx, s.name FROM stages s JOIN campaigns c ON c.id = s.campaign_id WHERE s.id = ?",
        (stage_id,)).fetchone()
    database = os.path.abspath(db_path)
    run = os.path.join(os.path.dirname(database), run_dir) if run_dir else f"{database}.runs/{campaign}"
    stage = f"stage-{stage_index}-" + re.sub(rb"[^A-Za-z0-9._-]", b"_", stage_name.encode()[:64]).decode()
    return os.path.join(os.path.normpath(run), stage, f"trial-{trial_index}", "trial.log")
