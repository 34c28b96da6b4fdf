#!/usr/bin/env bash
# Remakes the 15 authored style curves (5 styles × T of 2.5, 5.1 and 7.6 s, curve get-up seed
# §5.5's durations) with `podium tool getup_curves`, from ../shared/data's labelled get-up clips.
# The styles follow Bohannon and Lusardi's strategies (seed §2, Fig. 8-9): the class means of
# `stats` (9 samples per clip) where our clips have the class, edits of them where they do not.
#   situp_rollover  sit-up and roll-over: faceup.json (the one clip of the class)
#   pushup_prone    quadruped push-up from prone: the mean of the 5 prone push-up clips
#   pushup_supine   quadruped push-up from supine (no clip does it): the prone mean with a roll from
#                   the back first (θ_z 5° → 90° → prone, θ_x through the side), a supine drop
#   sidesit_pivot   side-sit to half-kneel pivot: 140_03, started on the back (θ_z 5°, θ_x 90°) as
#                   a drop can only land supine or prone and §5.2's 30° filter compares the two
#   pushup_kneel    the prone push-up with a kneeling pause (h's control points 5 and 6 lowered)
# Usage: make_styles.sh [PODIUM] (default: build/bin/podium of the repository); needs
# PODIUM_SHARED_DIR or ../shared beside the repository.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../../.." && pwd)
podium=${1:-$root/build/bin/podium}
export PODIUM_SHARED_DIR=${PODIUM_SHARED_DIR:-$root/../shared}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$here"
"$podium" tool getup_curves stats ../getup_labels.json --method samples --out "$tmp/stats.json" >/dev/null
# A class's mean curve as a curve file (the stats file holds it as a curve object).
mean_curve() {  # CLASS NAME SOURCE
  python3 - "$tmp/stats.json" "$1" "$2" "$3" "$tmp/$2.json" <<'PY'
import json, sys
stats, cls, name, source, out = sys.argv[1:]
curve = next(s["mean_curve"] for s in json.load(open(stats))["strategies"] if s["mean_curve"]["name"] == cls)
curve.update(name=name, source=source)
json.dump(curve, open(out, "w"), indent=2, ensure_ascii=False)
PY
}
edit() { "$podium" tool getup_curves edit "$@" >/dev/null; }
mean_curve quadruped_push_up_prone base_pushup_prone \
  "the mean of the 5 prone push-up clips' 9-sample curves (podium tool getup_curves stats --method samples), humanoid34's heights"
mean_curve side_sit_half_kneel_pivot base_sidesit_pivot \
  "140_03's 9-sample curve (podium tool getup_curves stats --method samples), humanoid34's heights"
edit "$tmp/base_pushup_prone.json" --out "$tmp/base_pushup_supine.json" --name base_pushup_supine \
  --move theta_z:0:-162 --move theta_z:1:-81 --move theta_x:1:67
python3 - "$tmp/base_pushup_supine.json" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
c["start"] = {"drop": "supine"}
c["source"] = ("authored: the prone push-up mean with a roll from the back first (θ_z 5° → 90° → prone, θ_x through "
               "the side at its 2nd control point), started as a supine drop")
json.dump(c, open(sys.argv[1], "w"), indent=2, ensure_ascii=False)
PY
edit "$tmp/base_pushup_prone.json" --out "$tmp/base_pushup_kneel.json" --name base_pushup_kneel --move h:5:-0.24 --move h:6:-0.3
edit "$tmp/base_sidesit_pivot.json" --out "$tmp/base_sidesit_back.json" --name base_sidesit_pivot \
  --move theta_z:0:-73 --move theta_x:0:-78
declare -A base=([situp_rollover]=faceup.json [pushup_prone]=$tmp/base_pushup_prone.json
                 [pushup_supine]=$tmp/base_pushup_supine.json [sidesit_pivot]=$tmp/base_sidesit_back.json
                 [pushup_kneel]=$tmp/base_pushup_kneel.json)
for style in situp_rollover pushup_prone pushup_supine sidesit_pivot pushup_kneel; do
  T=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['duration_s'])" "${base[$style]}")
  for target in 2.5 5.1 7.6; do
    tag=t${target/./}
    edit "${base[$style]}" --out "${style}_$tag.json" --name "${style}_$tag" \
      --scale-T "$(python3 -c "import sys; print(repr(float(sys.argv[1]) / float(sys.argv[2])))" "$target" "$T")"
  done
done
echo "make_styles.sh: 15 style curves written in $here"
