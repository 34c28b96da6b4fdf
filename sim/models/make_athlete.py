#!/usr/bin/env python3
"""Derives athlete.json, the thesis's simulated athlete, from humanoid34.json (standard library only).

    python3 sim/models/make_athlete.py        # rewrites sim/models/athlete.json; deterministic

Where each figure comes from (thesis = the seed thesis, whose chapter 3 is "Discovering Diverse Athletic Jumping
Strategies"):
- 60 kg, 170 cm tall, hip height 95 cm, knee height 46 cm: Table 3.2, "Simulated Athlete".
  Heights are taken in the standing pose: the top of the head, the hip and knee joint centres.
- 34 DoFs, 28 internal (§3.6.2): humanoid34's joints (chest, neck, hips, ankles, shoulders
  spherical; knees, elbows revolute), unchanged, with its swing/twist limits (DeepMimic's ranges).
- Segment masses: humanoid34's, which are DeepMimic's humanoid3d / the thesis's
  humanoid3d_jumper60kg.txt body masses (8 + 18.67 + 2.67 + 2 × 15.33 = 60 kg): kept as they are.
- Torque limits of hips, knees and ankles: §3.6.2 takes them "from Biomechanics estimations for a
  human athlete performing a Fosbury flop"; the values are those of the thesis's character file,
  arpspoof/Jump data/characters/humanoid3d_jumper60kg.txt (TorqueLimX/Y/Z in DeepMimic's y-up
  joint frame; x, y, z there are x, z, -y here): hips X 500, Y 50, Z 500 -> [500, 500, 50] about
  our x, y, z (abduction, flexion, twist); knees 400; ankles X 100, Y 50, Z 300 -> [100, 300, 50].
  tests/sim/athlete_test.cpp compares them with that file when the captured jump data is present (PODIUM_SHARED_DIR).
- Other joints' torque limits: "kept the same as [88]" (§3.6.2; [88] is DeepMimic), i.e.
  humanoid34's: chest 200, neck 50, shoulders 100, elbows 60 N·m. (The jumper file itself gives
  its shoulders 100/50/100 and elbows 50; the thesis's text is followed here.)
- PD gains: humanoid34's (DeepMimic's humanoid3d_ctrl.txt, which the jumper's controller file
  repeats), kd = kp / 10.

Shape: humanoid34 is DeepMimic's humanoid3d scaled by 1.174 (190 cm, hips 103 cm, knees 54 cm).
Three segments are rescaled so that the Table 3.2 heights hold exactly:
- above the hips (pelvis, chest, head, arms, the hips' lateral offsets): uniformly by
  (170 - 95) / (humanoid34's head top - hip height);
- thighs along their length by (95 - 46) / (humanoid34's hip - knee height);
- shins and feet along their length by 46 / humanoid34's knee height (which gives back
  DeepMimic's own shin and foot: 41.0 cm knee to ankle, 5.0 cm ankle to sole);
- the legs' radii, widths and the feet's lengths by the stature ratio 170 / humanoid34's height.
"""
import json
import pathlib

HERE = pathlib.Path(__file__).resolve().parent

# Table 3.2, "Simulated Athlete".
HEIGHT_M, HIP_M, KNEE_M, MASS_KG = 1.70, 0.95, 0.46, 60.0

# Per-joint torque limits, N·m ([x, y, z] about the link axes for per-axis spherical joints); see above.
TORQUE_LIMITS = {
    "hip": [500, 500, 50],
    "knee": 400,
    "ankle": [100, 300, 50],
}

LEG = {"thigh": "thigh", "shin": "shank", "foot": "shank"}  # body suffix -> segment


def figures(model):
    """Standing heights of humanoid34-shaped models: all frames are parallel at q = 0."""
    bodies = {b["name"]: b for b in model["bodies"]}
    root = model["standing_root_height"]
    hip = root + bodies["right_thigh"]["pos"][2]
    knee = hip + bodies["right_shin"]["pos"][2]
    foot = bodies["right_foot"]
    ankle = knee + foot["pos"][2]
    box = foot["geoms"][0]
    sole = ankle + box["pos"][2] - box["half_extents"][2]
    head = bodies["head"]
    sphere = head["geoms"][0]
    top = root + bodies["chest"]["pos"][2] + head["pos"][2] + sphere["pos"][2] + sphere["radius"]
    mass = sum(b["mass"] for b in model["bodies"])
    return {"height": top - sole, "hip": hip - sole, "knee": knee - sole, "sole": sole, "mass": mass}


def segment(name):
    for suffix, seg in LEG.items():
        if name.endswith("_" + suffix):
            return seg
    return "upper"


def scaled(v, s):
    """A point or size scaled per axis by s = (sx, sy, sz)."""
    return [round(x * k, 4) for x, k in zip(v, s)]


def main():
    h34 = json.loads((HERE / "humanoid34.json").read_text())
    f = figures(h34)
    assert abs(f["sole"]) < 1e-3, f
    assert all(b["pos"][2] == 0 for b in h34["bodies"] if b["name"].endswith("_thigh")), "hips off the root's height"
    assert abs(f["mass"] - MASS_KG) < 1e-6, f
    upper = (HEIGHT_M - HIP_M) / (f["height"] - f["hip"])
    thigh = (HIP_M - KNEE_M) / (f["hip"] - f["knee"])
    shank = KNEE_M / f["knee"]
    girth = HEIGHT_M / f["height"]
    factors = {"upper": (upper,) * 3, "thigh": (girth, girth, thigh), "shank": (girth, girth, shank)}

    bodies = []
    for b in h34["bodies"]:
        seg = segment(b["name"])
        s = factors[seg]
        out = dict(b)
        # A body's offset is a point of its parent (the knee is a point of the thigh): parent's scale.
        out["pos"] = scaled(b["pos"], factors[segment(b["parent"])]) if "parent" in b else list(b["pos"])
        geoms = []
        for g in b["geoms"]:
            g = dict(g)
            if g["type"] == "capsule":
                g["fromto"] = scaled(g["fromto"][:3], s) + scaled(g["fromto"][3:], s)
                g["radius"] = round(g["radius"] * s[0], 4)
            elif g["type"] == "sphere":
                g["pos"] = scaled(g["pos"], s)
                g["radius"] = round(g["radius"] * s[0], 4)
            else:
                g["pos"] = scaled(g["pos"], s)
                g["half_extents"] = scaled(g["half_extents"], s)
            geoms.append(g)
        out["geoms"] = geoms
        if "joints" in b:
            joints = []
            for j in b["joints"]:
                j = dict(j)
                kind = j["name"].split("_", 1)[-1]
                if kind in TORQUE_LIMITS:
                    j["torque_limit"] = TORQUE_LIMITS[kind]
                joints.append(j)
            out["joints"] = joints
        bodies.append(out)

    athlete = {
        "name": "athlete",
        "source": (
            "The thesis's simulated athlete (Table 3.2: 60 kg, 1.70 m, hip height 0.95 m, knee height 0.46 m; "
            "34 DoFs as humanoid34, §3.6.2), derived from humanoid34.json by sim/models/make_athlete.py (which says "
            "where each figure comes from): segments above the hips, thighs and shins rescaled so the heights hold, "
            "masses and gains as humanoid34; torque limits of hips [500, 500, 50], knees 400 and ankles [100, 300, 50] N·m "
            "(per axis about the link's x, y, z) from the thesis's humanoid3d_jumper60kg.txt, other joints as humanoid34 (DeepMimic)."
        ),
    }
    for key in ("head", "torso", "end_effectors"):
        athlete[key] = h34[key]
    athlete["bodies"] = bodies
    # The hips sit at the root's height (humanoid34's thighs hang from z = 0 of the pelvis).
    athlete["standing_root_height"] = HIP_M
    got = figures(athlete)
    assert abs(got["sole"]) < 1e-3, got  # the soles on the ground
    for key, want in (("height", HEIGHT_M), ("hip", HIP_M), ("knee", KNEE_M), ("mass", MASS_KG)):
        assert abs(got[key] - want) < 1e-3, (key, got[key], want)
    (HERE / "athlete.json").write_text(json.dumps(athlete, indent=1, ensure_ascii=False) + "\n")
    print("athlete.json: %.3f m, hips %.3f m, knees %.3f m, %.2f kg (scales: upper %.4f, thigh %.4f, shank %.4f, girth %.4f)"
          % (got["height"], got["hip"], got["knee"], got["mass"], upper, thigh, shank, girth))


if __name__ == "__main__":
    main()
