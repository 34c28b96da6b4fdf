#!/usr/bin/env bash
# The README's picture: the demo database's get-up replay (pi_weak fast beside its slowed
# imitation, from the same fall) above the campaign page's strategy gallery, served by
# `podium serve` and shot with headless Chromium (scripts/screenshot.mjs).
# Usage: scripts/screenshot.sh [DB] [OUT.png]   (defaults: runs/demo.db, docs/images/demo.png;
# run scripts/demo.sh first)
set -euo pipefail
cd "$(dirname "$0")/.."
db="${1:-runs/demo.db}"
out="${2:-docs/images/demo.png}"
[ -f "$db" ] || { echo "screenshot: $db: no such database (run scripts/demo.sh first)" >&2; exit 2; }
podium=build/bin/podium

campaign=getup-demo
trial=$("$podium" trials "$campaign" --db "$db" --json | /usr/bin/python3 -c '
import json, sys
ids = [t["id"] for t in json.load(sys.stdin) if t["name"] == "slowed/0" and t["state"] == "done"]
print(ids[0] if ids else "")')
[ -n "$trial" ] || { echo "screenshot: $db: campaign $campaign has no done trial slowed/0" >&2; exit 2; }
campaign_id=$("$podium" status "$campaign" --db "$db" --json | /usr/bin/python3 -c 'import json, sys; print(json.load(sys.stdin)["id"])')

tmp=$(mktemp -d)
port=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
"$podium" serve --db "$db" --port "$port" >"$tmp/serve.log" 2>&1 &
server=$!
trap 'kill "$server" 2>/dev/null || true; wait "$server" 2>/dev/null || true; rm -rf "$tmp"' EXIT
base="http://127.0.0.1:$port"
/usr/bin/python3 - "$base" <<'PY'
import sys, time, urllib.request
for _ in range(100):  # the server is up when it answers
    try:
        urllib.request.urlopen(sys.argv[1] + "/api/version", timeout=1)
        sys.exit(0)
    except OSError:
        time.sleep(0.1)
sys.exit("screenshot: podium serve did not answer")
PY

mkdir -p "$(dirname "$out")"
node scripts/screenshot.mjs "$base/" "$campaign_id" "$trial" "$(realpath -m "$out")"
[ -s "$out" ] || { echo "screenshot: no $out written" >&2; exit 1; }
echo "screenshot: $out ($(stat -c %s "$out") bytes) from $db"
