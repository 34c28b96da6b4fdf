#!/usr/bin/env bash
# The demo, end to end: installs what is missing, builds, runs the demo campaign (the shipped
# get-up policy pair from falls no training saw, fast and slowed; the shipped high-jump and obstacle-jump strategies;
# a smoke-sized Discover + Weaker training stage; edits of a style curve replayed by the shipped
# style-curve policy), prints its summary (`podium summary --short`:
# per stage a short table) and the page to open first.
# Usage: scripts/demo.sh [SPEC.json]   (default campaigns/getup_demo.json; campaigns/demo.json is
# the strategy-search demo on an analytic landscape)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
spec="${1:-campaigns/getup_demo.json}"
mkdir -p runs
db="$PWD/runs/demo.db"
# The jump trials name their nearest captured technique when the captured jumps (arpspoof/Jump's
# data/motions/beyond, not shipped: see docs/tasks/jump.md) are beside the repository as the tests
# find them (PODIUM_SHARED_DIR, default ../shared).
set_args=()
captured="${PODIUM_SHARED_DIR:-$PWD/../shared}/data/jump/data/motions/beyond"
if [ "$spec" = campaigns/getup_demo.json ] && [ -d "$captured" ]; then
  set_args=(--set "stages[2].config.captured_motions=$(cd "$captured" && pwd)")
fi
id=$(build/bin/podium submit "$spec" "${set_args[@]}" --db "$db")
echo "demo: submitted $spec as campaign $id in $db"
start=$(date +%s)
build/bin/podium run --db "$db" --workers 2
echo "demo: the campaign ran in $(( $(date +%s) - start )) s"
echo
# The same summary as `podium summary` and the campaign page's first panel.
build/bin/podium summary "$id" --short --db "$db"
echo
echo "demo: database   $db"
echo "demo: trials     build/bin/podium trials $id --db $db"
echo "demo: dashboard  build/bin/podium serve --db $db"
echo "demo: open first http://127.0.0.1:8080/campaign.html?id=$id"
echo "                 (the strategy gallery plays each strategy side by side; a trial's page links its"
echo "                 3D replays: the get-up fast beside slowed by kappa and paused, a jump over its bar)"
