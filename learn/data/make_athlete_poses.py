#!/usr/bin/env python3
"""Writes athlete_poses.json, the project's own pose set for the athlete (sim/models/athlete.json,
humanoid34's joints): the default training set of the jump task's P-VAE (thesis §3.4.2, which
trains on ~20,000 captured CMU/SFU poses; the project ships a set of its own so the jump needs no
third-party data, and the captured clips of the authors' data release stay optional).

    python3 learn/data/make_athlete_poses.py     # rewrites learn/data/athlete_poses.json; deterministic

Poses are authored, not captured. Each family below is a few keyframes in anatomical angles
(degrees: flexion, abduction, rotation per joint; see ANGLES) taken from textbook gait and jump
kinematics; a pose is a random point between two consecutive keyframes (linear interpolation),
its amplitudes scaled by a few per cent, plus Gaussian noise, randomly mirrored left <-> right.
Families: standing, a walking, a running and a sprinting cycle, a one-leg sprint take-off (plant,
compression, extension with a free-knee drive and arm lift), two-foot jumps (crouch, extension,
tuck), an arched-back layout like a Fosbury flop and its leg kick-out, straddle-like leg splits,
scissor kicks, landings on the feet and on the back, arm swings, bending, squats and lunges,
lying, sitting and rolling.

Layout (learn/pose_data.h, character/pose_bridge.h): the model's joints in link order, one angle
per revolute joint, an exponential map (rad, z-up link frames: x forward, y left, z up) per
spherical joint. Every pose is projected into the model's limits: hinge ranges, and for spherical
joints the swing cone about the link's z axis and the twist about it (the swing-twist split of
sim/src/contact_solver.cpp), with a small margin so rounding stays inside. Values are rounded to
0.01 rad to keep the file small.
"""
import json
import math
import pathlib
import random

HERE = pathlib.Path(__file__).resolve().parent
MODEL = HERE.parent.parent / "sim" / "models" / "athlete.json"
OUT = HERE / "athlete_poses.json"
SEED, COUNT, DIGITS, MARGIN = 19, 2400, 2, 0.02
NOISE_DEG = 3.0

# Anatomical angles of one pose, degrees; a missing key is 0. Sides: "r_" and "l_".
#   trunk_flex (forward bend +, arch -), trunk_side (lean left +), trunk_twist (turn left +),
#   neck_flex, neck_side, neck_twist likewise; per side: hip_flex (thigh forward +), hip_abd
#   (outward +), hip_rot (inward +), knee (bend +), ankle (toes down +), ankle_inv (sole inward +),
#   sh_flex (arm forward/up +), sh_abd (arm outward/up +), sh_rot (inward +), elbow (bend +).
SIDED = ["hip_flex", "hip_abd", "hip_rot", "knee", "ankle", "ankle_inv", "sh_flex", "sh_abd", "sh_rot", "elbow"]
MIDLINE = ["trunk_flex", "trunk_side", "trunk_twist", "neck_flex", "neck_side", "neck_twist"]
ANGLES = MIDLINE + ["r_" + k for k in SIDED] + ["l_" + k for k in SIDED]


def legs(side, hip, knee, ankle, abd=5, rot=0):
    return {side + "hip_flex": hip, side + "knee": knee, side + "ankle": ankle, side + "hip_abd": abd, side + "hip_rot": rot}


def arms(side, flex, abd, elbow, rot=0):
    return {side + "sh_flex": flex, side + "sh_abd": abd, side + "elbow": elbow, side + "sh_rot": rot}


def pose(*parts, **midline):
    p = dict(arms("r_", 0, 8, 12)) | arms("l_", 0, 8, 12)  # arms hang relaxed unless a part says otherwise
    for part in parts:
        p |= part
    return p | midline


def cycle(table, phase):
    """Piecewise-linear periodic curve through (phase, value) points."""
    pts = table + [(table[0][0] + 1.0, table[0][1])]
    phase %= 1.0
    for (a, va), (b, vb) in zip(pts, pts[1:]):
        if a <= phase <= b:
            return va + (vb - va) * (phase - a) / (b - a)
    return table[0][1]


# Gait cycles from heel (foot) strike, per leg: hip flexion, knee flexion, ankle plantarflexion;
# the other leg runs half a cycle later, each arm swings against its leg.
GAITS = {
    "walk": dict(hip=[(0, 25), (0.15, 20), (0.5, -12), (0.62, -5), (0.85, 30)],
                 knee=[(0, 5), (0.15, 18), (0.4, 5), (0.6, 40), (0.72, 62), (0.9, 15)],
                 ankle=[(0, 0), (0.1, 8), (0.45, -10), (0.62, 18), (0.75, 0)],
                 trunk=4, arm=0.7, elbow=20),
    "run": dict(hip=[(0, 30), (0.15, 15), (0.4, -15), (0.75, 55), (0.9, 40)],
                knee=[(0, 20), (0.15, 40), (0.4, 18), (0.65, 100), (0.85, 55)],
                ankle=[(0, 0), (0.15, -15), (0.4, 30), (0.6, 10), (0.9, 0)],
                trunk=10, arm=1.0, elbow=85),
    "sprint": dict(hip=[(0, 45), (0.12, 25), (0.35, -22), (0.7, 80), (0.88, 65)],
                   knee=[(0, 25), (0.12, 40), (0.35, 15), (0.6, 130), (0.8, 90), (0.92, 40)],
                   ankle=[(0, 10), (0.12, -15), (0.35, 40), (0.6, 15), (0.9, 5)],
                   trunk=16, arm=1.4, elbow=90),
}


def gait(rng, name):
    g, phase = GAITS[name], rng.random()
    p = pose(trunk_flex=g["trunk"], trunk_twist=-6 * math.sin(2 * math.pi * phase), neck_flex=-g["trunk"] / 2)
    for side, shift in (("r_", 0.0), ("l_", 0.5)):
        hip = cycle(g["hip"], phase + shift)
        p |= legs(side, hip, cycle(g["knee"], phase + shift), cycle(g["ankle"], phase + shift), abd=4)
        other = cycle(g["hip"], phase + shift + 0.5)  # the arm swings with the opposite leg
        p |= arms(side, g["arm"] * other, 10, g["elbow"] + 0.3 * other)
    return p


# Keyframe sequences: a pose is drawn between two consecutive frames.
SEQUENCES = {
    # One-leg sprint take-off (right foot plants): last stride, plant with the body leaning back,
    # compression, extension with the free (left) knee and both arms driving up, early flight.
    "takeoff": [
        pose(legs("r_", 45, 30, 5), legs("l_", -15, 60, 30), arms("r_", -40, 15, 80), arms("l_", 50, 15, 90), trunk_flex=5),
        pose(legs("r_", 35, 10, -10), legs("l_", -10, 90, 20), arms("r_", -45, 25, 60), arms("l_", -40, 25, 60),
             trunk_flex=-15, trunk_side=8, neck_flex=10),
        pose(legs("r_", 25, 40, -20), legs("l_", 40, 110, 10), arms("r_", 10, 20, 70), arms("l_", 10, 20, 70),
             trunk_flex=-10, trunk_side=5),
        pose(legs("r_", -10, 5, 45), legs("l_", 90, 95, 15, rot=10), arms("r_", 150, 20, 40), arms("l_", 150, 20, 40),
             trunk_flex=-5, trunk_side=-4, neck_flex=-10),
        pose(legs("r_", -5, 15, 35), legs("l_", 80, 80, 20), arms("r_", 160, 40, 20), arms("l_", 120, 30, 50),
             trunk_flex=-12, trunk_twist=20, neck_flex=-15),
    ],
    # Two-foot jump: stand, countermovement crouch, extension, tuck in flight, extend to land.
    "two_foot": [
        pose(legs("r_", 5, 5, 0), legs("l_", 5, 5, 0), arms("r_", 20, 10, 20), arms("l_", 20, 10, 20)),
        pose(legs("r_", 95, 110, -25), legs("l_", 95, 110, -25), arms("r_", -55, 15, 20), arms("l_", -55, 15, 20),
             trunk_flex=45, neck_flex=-25),
        pose(legs("r_", -5, 0, 45), legs("l_", -5, 0, 45), arms("r_", 165, 15, 15), arms("l_", 165, 15, 15),
             trunk_flex=-5, neck_flex=-10),
        pose(legs("r_", 115, 130, 15), legs("l_", 115, 130, 15), arms("r_", 60, 25, 80), arms("l_", 60, 25, 80),
             trunk_flex=35, neck_flex=20),
        pose(legs("r_", 30, 15, 20), legs("l_", 30, 15, 20), arms("r_", 70, 35, 30), arms("l_", 70, 35, 30), trunk_flex=10),
    ],
    # Arched-back layout over a bar (Fosbury flop): the back arches, hips extend, knees hang, then
    # the hips flex to kick the legs up and over, chin to chest.
    "flop": [
        pose(legs("r_", -10, 20, 30), legs("l_", 40, 70, 20), arms("r_", 100, 40, 30), arms("l_", 60, 30, 40),
             trunk_flex=-25, trunk_side=15, trunk_twist=25, neck_flex=-20),
        pose(legs("r_", -30, 70, 20, abd=20), legs("l_", -30, 70, 20, abd=20), arms("r_", -10, 30, 10),
             arms("l_", -10, 30, 10), trunk_flex=-55, neck_flex=-40),
        pose(legs("r_", -40, 100, 15, abd=25), legs("l_", -40, 100, 15, abd=25), arms("r_", 20, 60, 10),
             arms("l_", 20, 60, 10), trunk_flex=-65, neck_flex=-45),
        pose(legs("r_", 40, 30, 20), legs("l_", 40, 30, 20), arms("r_", 10, 45, 20), arms("l_", 10, 45, 20),
             trunk_flex=-10, neck_flex=30),
        pose(legs("r_", 90, 10, 30), legs("l_", 90, 10, 30), arms("r_", 30, 60, 20), arms("l_", 30, 60, 20),
             trunk_flex=40, neck_flex=40),
    ],
    # Straddle-like: the lead leg swings up straight, the body rolls face-down over the bar with
    # the trail leg abducted and bent, then both legs split wide.
    "straddle": [
        pose(legs("r_", -5, 10, 40), legs("l_", 100, 5, 20, abd=20), arms("r_", 120, 30, 30), arms("l_", 140, 30, 20),
             trunk_flex=-5, trunk_side=-10),
        pose(legs("r_", 20, 90, 20, abd=50, rot=-30), legs("l_", 95, 10, 20, abd=35), arms("r_", 60, 70, 40),
             arms("l_", 100, 50, 20), trunk_flex=35, trunk_twist=-20),
        pose(legs("r_", 10, 110, 10, abd=70, rot=-35), legs("l_", 60, 10, 25, abd=60), arms("r_", 40, 80, 30),
             arms("l_", 50, 80, 30), trunk_flex=45, trunk_side=10),
        pose(legs("r_", 45, 5, 40, abd=75), legs("l_", 45, 5, 40, abd=75), arms("r_", 70, 40, 10), arms("l_", 70, 40, 10),
             trunk_flex=55, neck_flex=20),
    ],
    # Scissor kicks: upright trunk, straight legs alternating high and low, arms out for balance.
    "scissor": [
        pose(legs("r_", -5, 10, 40), legs("l_", 85, 10, 20), arms("r_", 60, 70, 30), arms("l_", 80, 60, 30),
             trunk_flex=-10, trunk_side=8),
        pose(legs("r_", 60, 15, 30), legs("l_", 60, 15, 30), arms("r_", 40, 85, 20), arms("l_", 40, 85, 20), trunk_flex=-15),
        pose(legs("r_", 95, 10, 30), legs("l_", 10, 10, 35), arms("r_", 70, 60, 30), arms("l_", 50, 75, 30),
             trunk_flex=-5, trunk_side=-8),
        pose(legs("r_", 40, 40, 10), legs("l_", 10, 60, 10), arms("r_", 30, 50, 40), arms("l_", 30, 50, 40), trunk_flex=10),
    ],
    # Landing on the back (a high-jump mat) and rolling over the shoulders: tuck, legs up, roll.
    "back_landing": [
        pose(legs("r_", 80, 60, 20), legs("l_", 80, 60, 20), arms("r_", 20, 70, 20), arms("l_", 20, 70, 20),
             trunk_flex=30, neck_flex=40),
        pose(legs("r_", 120, 30, 30), legs("l_", 120, 30, 30), arms("r_", 0, 45, 10), arms("l_", 0, 45, 10),
             trunk_flex=55, neck_flex=50),
        pose(legs("r_", 100, 130, 30), legs("l_", 100, 130, 30), arms("r_", 150, 30, 130), arms("l_", 150, 30, 130),
             trunk_flex=60, neck_flex=50),
        pose(legs("r_", 40, 140, 40), legs("l_", 40, 140, 40), arms("r_", 60, 30, 60), arms("l_", 60, 30, 60), trunk_flex=30),
    ],
    # Forward roll and rising from the floor: crouch, hands down, tucked roll, sit, kneel, stand up.
    "roll": [
        pose(legs("r_", 110, 130, -20), legs("l_", 110, 130, -20), arms("r_", 70, 15, 20), arms("l_", 70, 15, 20),
             trunk_flex=55, neck_flex=45),
        pose(legs("r_", 125, 145, 30), legs("l_", 125, 145, 30), arms("r_", 40, 20, 110), arms("l_", 40, 20, 110),
             trunk_flex=65, neck_flex=55),
        pose(legs("r_", 90, 20, 20), legs("l_", 90, 20, 20), arms("r_", 40, 20, 20), arms("l_", 40, 20, 20), trunk_flex=10),
        pose(legs("r_", 0, 120, 40), legs("l_", 0, 120, 40), arms("r_", 10, 10, 20), arms("l_", 10, 10, 20)),
        pose(legs("r_", 90, 90, -10), legs("l_", -10, 95, 40), arms("r_", 20, 15, 30), arms("l_", 20, 15, 30), trunk_flex=10),
    ],
}


def free(rng, name):
    """Families drawn from ranges rather than sequences."""
    u = rng.uniform
    if name == "stand":
        p = pose(legs("r_", u(-5, 10), u(0, 15), u(-5, 10), abd=u(0, 12), rot=u(-10, 10)),
                 legs("l_", u(-5, 10), u(0, 15), u(-5, 10), abd=u(0, 12), rot=u(-10, 10)),
                 arms("r_", u(-15, 30), u(0, 25), u(0, 70)), arms("l_", u(-15, 30), u(0, 25), u(0, 70)),
                 trunk_flex=u(-5, 10), trunk_twist=u(-15, 15), neck_flex=u(-20, 25), neck_twist=u(-40, 40))
    elif name == "arm_swing":  # legs planted, arms anywhere in reach: forward, overhead, back, out
        p = pose(legs("r_", u(0, 30), u(0, 40), u(-15, 10)), legs("l_", u(0, 30), u(0, 40), u(-15, 10)),
                 arms("r_", u(-60, 175), u(0, 100), u(0, 120), rot=u(-40, 40)),
                 arms("l_", u(-60, 175), u(0, 100), u(0, 120), rot=u(-40, 40)),
                 trunk_flex=u(-15, 20), trunk_twist=u(-35, 35), trunk_side=u(-10, 10))
    elif name == "bend":  # toe touches, side bends, squats and lunges
        kind, s = rng.choice(["toes", "side", "squat", "lunge"]), rng.random()
        if kind == "toes":
            p = pose(legs("r_", 90 * s, 15 * s, 0), legs("l_", 90 * s, 15 * s, 0), arms("r_", 90 * s, 10, 10),
                     arms("l_", 90 * s, 10, 10), trunk_flex=60 * s, neck_flex=20 * s)
        elif kind == "side":
            p = pose(legs("r_", 0, 5, 0, abd=u(5, 20)), legs("l_", 0, 5, 0, abd=u(5, 20)), arms("r_", 0, 160 * s, 20),
                     arms("l_", 0, 20, 20), trunk_side=40 * s, trunk_twist=u(-10, 10))
        elif kind == "squat":
            p = pose(legs("r_", 115 * s, 135 * s, -25 * s, abd=15), legs("l_", 115 * s, 135 * s, -25 * s, abd=15),
                     arms("r_", 90 * s, 10, 20), arms("l_", 90 * s, 10, 20), trunk_flex=40 * s)
        else:
            p = pose(legs("r_", 80 * s, 90 * s, -15 * s), legs("l_", -15 * s, 80 * s, 35 * s), arms("r_", u(0, 40), 15, 30),
                     arms("l_", u(0, 40), 15, 30), trunk_flex=u(-5, 15))
    else:  # "lying": on the back, front or side, or sitting, limbs anywhere comfortable
        p = pose(legs("r_", u(-10, 90), u(0, 120), u(0, 45), abd=u(0, 35)),
                 legs("l_", u(-10, 90), u(0, 120), u(0, 45), abd=u(0, 35)),
                 arms("r_", u(-30, 170), u(0, 120), u(0, 120), rot=u(-40, 40)),
                 arms("l_", u(-30, 170), u(0, 120), u(0, 120), rot=u(-40, 40)),
                 trunk_flex=u(-20, 40), trunk_side=u(-15, 15), trunk_twist=u(-20, 20), neck_flex=u(-20, 40),
                 neck_twist=u(-50, 50))
    return p


# Poses per family, out of COUNT (the running and jumping families weigh most: the task's motions).
WEIGHTS = {"stand": 4, "walk": 6, "run": 8, "sprint": 8, "takeoff": 12, "two_foot": 8, "flop": 10, "straddle": 7,
           "scissor": 7, "back_landing": 6, "roll": 6, "arm_swing": 6, "bend": 7, "lying": 5}


def draw(rng, family):
    if family in GAITS:
        p = gait(rng, family)
    elif family in SEQUENCES:
        frames = SEQUENCES[family]
        i, t = rng.randrange(len(frames) - 1), rng.random()
        a, b = frames[i], frames[i + 1]
        p = {k: (1 - t) * a.get(k, 0.0) + t * b.get(k, 0.0) for k in set(a) | set(b)}
    else:
        p = free(rng, family)
    scale = rng.uniform(0.9, 1.08)
    p = {k: scale * p.get(k, 0.0) + rng.gauss(0.0, NOISE_DEG) for k in ANGLES}
    return mirrored(p) if rng.random() < 0.5 else p


def mirrored(p):
    """Left <-> right: sided angles swap; the midline's sideways lean and turns change sign."""
    out = {k: -v if k.endswith(("_side", "_twist")) else v for k, v in p.items() if k in MIDLINE}
    for k in SIDED:
        out["r_" + k], out["l_" + k] = p["l_" + k], p["r_" + k]
    return out


# --- rotations: quaternions (w, x, y, z) --------------------------------------------------------

def axis_quat(axis, deg):
    h = math.radians(deg) / 2
    v = [0.0, 0.0, 0.0]
    v["xyz".index(axis)] = math.sin(h)
    return (math.cos(h), *v)


def qmul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw)


def euler(y_deg, x_deg, z_deg):
    """R = Ry · Rx · Rz: flexion about y, then sideways about x, then twist about the bone (z)."""
    return qmul(qmul(axis_quat("y", y_deg), axis_quat("x", x_deg)), axis_quat("z", z_deg))


def joint_rotation(joint, p):
    """A spherical joint's rotation from anatomical angles. x forward, y left, z up: flexing a
    limb forward is a negative turn about y, the trunk bending forward a positive one; a right
    limb abducts by a negative turn about x, a left one by a positive one."""
    side = "r_" if joint.startswith("right") else "l_"
    out = -1.0 if side == "r_" else 1.0
    if joint in ("chest", "neck"):
        pre = "trunk" if joint == "chest" else "neck"
        return euler(p[pre + "_flex"], -p[pre + "_side"], p[pre + "_twist"])
    if joint.endswith("hip"):
        return euler(-p[side + "hip_flex"], out * p[side + "hip_abd"], -out * p[side + "hip_rot"])
    if joint.endswith("ankle"):
        return euler(p[side + "ankle"], -out * p[side + "ankle_inv"], 0.0)
    return euler(-p[side + "sh_flex"], out * p[side + "sh_abd"], -out * p[side + "sh_rot"])  # shoulder


def within_limits(q, swing_limit, twist_lo, twist_hi):
    """Projects q into the swing cone and twist range about z (q = q_swing · q_twist)."""
    w, x, y, z = q if q[0] >= 0 else tuple(-c for c in q)
    n = math.hypot(w, z)
    tw = (w / n, 0.0, 0.0, z / n) if n > 1e-9 else (1.0, 0.0, 0.0, 0.0)
    sw = qmul((w, x, y, z), (tw[0], 0.0, 0.0, -tw[3]))
    twist = 2 * math.atan2(tw[3], tw[0])
    swing = 2 * math.atan2(math.hypot(sw[1], sw[2], sw[3]), sw[0])
    twist = min(max(twist, twist_lo + MARGIN), twist_hi - MARGIN)
    if swing > swing_limit - MARGIN:
        s = math.sin((swing_limit - MARGIN) / 2) / math.hypot(sw[1], sw[2], sw[3])
        sw = (math.cos((swing_limit - MARGIN) / 2), sw[1] * s, sw[2] * s, sw[3] * s)
    return qmul(sw, (math.cos(twist / 2), 0.0, 0.0, math.sin(twist / 2)))


def log_map(q):
    w, x, y, z = q if q[0] >= 0 else tuple(-c for c in q)
    s = math.hypot(x, y, z)
    if s < 1e-12:
        return [0.0, 0.0, 0.0]
    k = 2 * math.atan2(s, w) / s
    return [k * x, k * y, k * z]


def joints(model):
    """(name, type, limits) of each actuated joint in link order, as character::PoseBridge lists them."""
    out = []
    for body in model["bodies"]:
        for j in body.get("joints", []):
            if j["type"] == "revolute":
                out.append((j["name"], "revolute", tuple(j["range"])))
            else:
                assert "axis" not in j, "twist axis other than z"
                out.append((j["name"], "spherical", (j["swing"], *j["twist"])))
    return out


def to_pose(p, layout):
    values = []
    for name, kind, limits in layout:
        if kind == "revolute":
            side = "r_" if name.startswith("right") else "l_"
            # Both hinges turn about −y: a knee bends (foot back) at q < 0, an elbow (hand forward) at q > 0.
            angle = -math.radians(p[side + "knee"]) if name.endswith("knee") else math.radians(p[side + "elbow"])
            lo, hi = limits
            values.append(min(max(angle, lo), hi))
        else:
            values += log_map(within_limits(joint_rotation(name, p), *limits))
    return [quantized(v) for v in values]


def quantized(v):
    """Rounded to DIGITS decimals, whole numbers written without ".0" (the file stays small)."""
    v = round(v, DIGITS)
    return int(v) if v == int(v) else v


def main():
    model = json.loads(MODEL.read_text())
    layout = joints(model)
    names, lower, upper = [], [], []
    for name, kind, limits in layout:
        if kind == "revolute":
            names.append(name)
            lower.append(limits[0])
            upper.append(limits[1])
        else:
            names += [name + "_x", name + "_y", name + "_z"]
            lower += [-math.pi] * 3
            upper += [math.pi] * 3
    rng = random.Random(SEED)
    total = sum(WEIGHTS.values())
    poses = []
    for family, weight in WEIGHTS.items():
        poses += [to_pose(draw(rng, family), layout) for _ in range(round(COUNT * weight / total))]
    rng.shuffle(poses)
    OUT.write_text(json.dumps({
        "description": "Podium's authored pose set for the athlete (sim/models/athlete.json); see make_athlete_poses.py",
        "dof_names": names, "lower": lower, "upper": upper,
        "poses": poses}, separators=(",", ":")) + "\n")


if __name__ == "__main__":
    main()
