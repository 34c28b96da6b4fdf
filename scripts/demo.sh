#!/usr/bin/env bash
# The demo, end to end: installs what is missing, builds, runs the get-up demo campaign (the
# shipped get-up policies from fresh falls at several strengths and speeds, then a smoke-sized
# Discover + Weaker training stage) and prints where the results and the motions are.
# Usage: scripts/demo.sh [SPEC.json]   (default campaigns/getup_demo.json; campaigns/demo.json is
# the strategy-search demo on an analytic landscape)
set -euo pipefail
cd "$(dirname "$0")/.."   # the shipped policies' paths in the spec are relative to the repository
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
build/bin/podium status "$id" --db "$db"
build/bin/podium trials "$id" --db "$db"
build/bin/podium export "$id" --format json --db "$db" | /usr/bin/python3 -c "$(cat <<'PY'
import json, sys
rows = json.load(sys.stdin)
for stage in dict.fromkeys(r["stage"] for r in rows):
    done = [r for r in rows if r["stage"] == stage and r["state"] == "done"]
    strategies = len({r["strategy"] for r in done})
    print(f"demo: stage {stage}: {len(done)} trials done, {strategies} distinct strategies")
    for r in done:
        for s in (r.get("result") or {}).get("speeds", []):
            what = f"strength {s['strength']:.3f}" if s["strength"] > 0 else (f"kappa {s['kappa']:g}" if s["name"] != "pause" else "paused")
            # drops: how often a risen head fell back below the height (standing: 0; a leap loop: 2-4);
            # stood: up without a break for the last 2 s (a leap's flight is shorter)
            print(f"demo:   {r['name']} {s['name']:>10} ({what}): up at the end {s['success_rate']:.2f}, "
                  f"rose {s['risen']} ({s['risen_on_back']} of the {s['on_back']} on the back), stood {s['stood']}, drops {s['drops']:.1f}, rise {s['rise_time_s']:.2f} s, COM error {s['com_error_m']:.3f} m"
                  + (f" over {100 * s['tracked_fraction']:.0f}% of the rise, {s['end_com_gap_m']:.2f} m below at its end" if s["kappa"] > 0 else ""))
        summary = (r.get("result") or {}).get("summary")
        if summary and "speeds" not in (r.get("result") or {}):
            print(f"demo:   {r['name']}: " + ", ".join(f"{k} {v:.3g}" if isinstance(v, float) else f"{k} {v}" for k, v in summary.items()))
PY
)"
echo
echo "demo: database      $db"
echo "demo: run folder    $(build/bin/podium status "$id" --db "$db" --json | /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["run_dir"])')"
echo "demo: trials        build/bin/podium trials $id --db $db"
echo "demo: dashboard     build/bin/podium serve --db $db   (then open http://127.0.0.1:8080/campaign.html?id=$id;"
echo "                    the strategy gallery plays each strategy; a trial's page links its 3D replays:"
echo "                    the get-up fast, slowed by kappa, and paused; a jump over its bar)"
