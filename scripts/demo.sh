#!/usr/bin/env bash
# The demo, end to end: installs what is missing, builds, runs the demo campaign (the shipped
# get-up policy pair from falls no training saw, fast and slowed; the shipped high-jump strategies;
# a smoke-sized Discover + Weaker training stage), prints a short table per stage and the page to
# open first. Usage: scripts/demo.sh [SPEC.json]   (default campaigns/getup_demo.json;
# campaigns/demo.json is the strategy-search demo on an analytic landscape)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
spec="${1:-campaigns/getup_demo.json}"
mkdir -p runs
db="$PWD/runs/demo.db"
id=$(build/bin/podium submit "$spec" --db "$db")
echo "demo: submitted $spec as campaign $id in $db"
start=$(date +%s)
build/bin/podium run --db "$db" --workers 2
echo "demo: the campaign ran in $(( $(date +%s) - start )) s"
echo
build/bin/podium export "$id" --format json --db "$db" | /usr/bin/python3 -c "$(cat <<'PY'
import json, sys

def table(header, rows):
    # text columns left, number columns right
    widths = [max(len(str(c)) for c in col) for col in zip(header, *rows)]
    left = [all(isinstance(row[i], str) and not row[i][:1].isdigit() for row in rows) for i in range(len(header))]
    for row in [header] + rows:
        print("  " + "  ".join(str(c).ljust(w) if l else str(c).rjust(w) for c, w, l in zip(row, widths, left)).rstrip())

def getup_evaluation(trials):
    # π_weak's fast runs and π_slow's slowed ones from the same falls. rose: the head top passed
    # 1.2 m; stood: it stayed above for the episode's last 2 s (a leap's flight is shorter).
    rows = []
    for t in trials:
        for s in t["result"]["speeds"]:
            falls = 20 if s["kappa"] == 0 else None
            what = (f"pi_weak fast, strength {s['strength']:g}" if s["kappa"] == 0
                    else "pi_slow paused" if s["name"] == "pause" else f"pi_slow kappa {s['kappa']:g}")
            back = f"{s['risen_on_back']}/{s['on_back']}" if falls else "-"
            com = f"{s['com_error_m']:.3f}" if s["kappa"] > 0 else "-"
            rows.append([what, s["risen"], back, s["stood"], f"{s['rise_time_s']:.2f}", com])
    table(["run (20 falls)", "rose", "rose from back", "stood", "rise s", "COM error m"], rows)

def jumps(trials):
    rows = []
    for t in trials:
        r = t["result"]
        name = r.get("policy", "").rsplit("/", 1)[-1].removesuffix(".pt")
        jumps = next((int(k.split()[2]) for k in r["summary"] if k.startswith("success over")), 0)
        cleared = f"{round(r['success_rate'] * jumps)}/{jumps}" if jumps else f"{r['success_rate']:.2f}"
        rows.append([t["name"], name, t["strategy"], f"{r['summary']['bar m']:.2f}", cleared, f"{r['up_angle_rad']:.3f}"])
    table(["trial", "policy", "strategy", "bar m", "cleared", "up-angle rad"], rows)

def training(trials):
    rows = [[t["name"], t["result"]["env_steps"], t["result"]["levels"], f"{t['result']['final_strength']:.3f}",
             f"{t['result']['test_return']:.2f}", t["strategy"]] for t in trials]
    table(["trial", "env steps", "advances", "strength", "test return", "strategy"], rows)

rows = json.load(sys.stdin)
for stage in dict.fromkeys(r["stage"] for r in rows):
    done = [r for r in rows if r["stage"] == stage and r["state"] == "done"]
    total = sum(r["stage"] == stage for r in rows)
    print(f"demo: stage {stage}: {len(done)} of {total} trials done, {len({r['strategy'] for r in done})} distinct strategies")
    results = [r.get("result") or {} for r in done]
    if done and all("speeds" in r for r in results): getup_evaluation(done)
    elif done and all("up_angle_rad" in r for r in results): jumps(done)
    elif done and all("levels" in r for r in results): training(done)
    else:
        table(["trial", "objectives", "strategy"], [[r["name"], " ".join(f"{o:.4g}" for o in r["objectives"]), r["strategy"]] for r in done])
    print()
PY
)"
echo "demo: database   $db"
echo "demo: trials     build/bin/podium trials $id --db $db"
echo "demo: dashboard  build/bin/podium serve --db $db"
echo "demo: open first http://127.0.0.1:8080/campaign.html?id=$id"
echo "                 (the strategy gallery plays each strategy side by side; a trial's page links its"
echo "                 3D replays: the get-up fast beside slowed by kappa and paused, a jump over its bar)"
