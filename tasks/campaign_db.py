"""Shared by the tasks' report.py scripts: a campaign's stages, read-only from its Podium database, and trial wall times."""
import sqlite3
import sys


def open_campaign(db_path, campaign):
    """(connection, [(stage id, stage name, task config JSON)]) of the newest campaign named `campaign`;
    exits with a one-line error when there is none."""
    db = sqlite3.connect(f"file:{db_path}?mode=ro", uri=True)
    row = db.execute("SELECT id FROM campaigns WHERE name = ? ORDER BY id DESC", (campaign,)).fetchone()
    if row is None:
        sys.exit(f"report.py: {db_path}: no campaign named {campaign!r}")
    stages = db.execute("SELECT id, name, task_config FROM stages WHERE campaign_id = ? ORDER BY idx", (row[0],)).fetchall()
    return db, stages


def minutes(started, finished):
    """A trial's wall time in minutes from its stored start and finish (NaN while either is missing)."""
    return (finished - started) / 60 if finished and started else float("nan")
