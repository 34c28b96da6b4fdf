#!/usr/bin/env bash
# The demo, end to end: installs what is missing, builds, runs the demo campaign and prints where
# the results are. Usage: scripts/demo.sh [SPEC.json]   (default campaigns/demo.json)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
spec="${1:-campaigns/demo.json}"
mkdir -p runs
db="$PWD/runs/demo.db"
id=$(build/bin/podium submit "$spec" --db "$db")
echo "demo: submitted $spec as campaign $id in $db"
build/bin/podium run --db "$db" --workers 2
build/bin/podium status "$id" --db "$db"
build/bin/podium export "$id" --format json --db "$db" | /usr/bin/python3 -c "$(cat <<'PY'
import json, sys
rows = json.load(sys.stdin)
for stage in dict.fromkeys(r["stage"] for r in rows):
    done = [r for r in rows if r["stage"] == stage and r["state"] == "done"]
    strategies = len({r["strategy"] for r in done})
    print(f"demo: stage {stage}: {strategies} distinct strategies in {len(done)} trials")
PY
)"
echo
echo "demo: database      $db"
echo "demo: run folder    $(build/bin/podium status "$id" --db "$db" --json | /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["run_dir"])')"
echo "demo: trials        build/bin/podium trials $id --db $db"
echo "demo: export        build/bin/podium export $id --format csv --db $db"
echo "demo: dashboard     build/bin/podium serve --db $db   (then open http://127.0.0.1:8080/)"
