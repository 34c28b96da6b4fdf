#!/usr/bin/env python3
"""Writes humanoid21_poses.json, the project's own small pose set for the 21-hinge humanoid of
the get-up seed (Table 2 joint names and angle limits). Poses are authored, not captured: a few
parametric families (standing, squats, lunges, kneeling, sitting, bending, arm raises and
reaches) with random parameters and small noise, clamped to the limits. Conditions for the C-VAE
(curve get-up seed §3.5): [pelvis height (m), torso pitch (rad), torso roll (rad)], with the
pelvis height from planar leg kinematics: 0.08 + 0.42·(cos(hip_y) + cos(hip_y − knee)), averaged
over both legs. Deterministic: python3 make_humanoid21_poses.py > humanoid21_poses.json"""
import json
import math
import random

# Table 2 of the get-up seed: name, lower, upper (rad).
JOINTS = [
    ("abdomen_z", -0.79, 0.79), ("abdomen_y", -1.31, 0.52), ("abdomen_x", -0.61, 0.61),
    ("right_hip_x", -0.44, 0.09), ("right_hip_z", -0.52, 0.44), ("right_hip_y", -1.92, 0.35),
    ("right_knee", -2.79, 0.03), ("right_ankle_y", -0.35, 0.79), ("right_ankle_x", -0.87, 0.87),
    ("left_hip_x", -0.44, 0.09), ("left_hip_z", -0.52, 0.44), ("left_hip_y", -1.92, 0.35),
    ("left_knee", -2.79, 0.04), ("left_ankle_y", -0.35, 0.79), ("left_ankle_x", -0.87, 0.87),
    ("right_shoulder1", -1.48, 1.05), ("right_shoulder2", -1.48, 1.05), ("right_elbow", -1.57, 0.87),
    ("left_shoulder1", -1.05, 1.48), ("left_shoulder2", -1.05, 1.48), ("left_elbow", -1.57, 0.87),
]
INDEX = {name: i for i, (name, _, _) in enumerate(JOINTS)}


def legs(p, side, hip, knee, ankle):
    p[INDEX[side + "_hip_y"]] = hip
    p[INDEX[side + "_knee"]] = knee
    p[INDEX[side + "_ankle_y"]] = ankle


def arms(p, rng, raise_, reach):
    p[INDEX["right_shoulder1"]] = -1.3 * raise_ + rng.gauss(0, 0.1)
    p[INDEX["left_shoulder1"]] = 1.3 * raise_ + rng.gauss(0, 0.1)
    p[INDEX["right_shoulder2"]] = -1.2 * reach + rng.gauss(0, 0.1)
    p[INDEX["left_shoulder2"]] = 1.2 * reach + rng.gauss(0, 0.1)
    p[INDEX["right_elbow"]] = -1.4 * rng.random()
    p[INDEX["left_elbow"]] = -1.4 * rng.random()


def pose(rng):
    p = [0.0] * len(JOINTS)
    family = rng.choice(["stand", "squat", "lunge", "kneel", "sit", "bend"])
    s = rng.random()
    if family == "stand":
        for side in ("right", "left"):
            legs(p, side, rng.gauss(0, 0.1), -0.2 * s, 0.1 * s)
    elif family == "squat":
        for side in ("right", "left"):
            legs(p, side, -1.7 * s, -2.5 * s, 0.6 * s)
        p[INDEX["abdomen_y"]] = -0.6 * s
    elif family == "lunge":
        front, back = rng.sample(["right", "left"], 2)
        legs(p, front, -1.3 * s, -1.6 * s, 0.4 * s)
        legs(p, back, 0.3 * s, -1.0 * s, -0.2 * s)
    elif family == "kneel":
        for side in ("right", "left"):
            legs(p, side, -0.3 * s, -2.6, -0.3)
        p[INDEX["abdomen_y"]] = -0.4 * s
    elif family == "sit":
        for side in ("right", "left"):
            legs(p, side, -1.6, -0.4 * s, 0.2)
        p[INDEX["abdomen_y"]] = 0.3 * s - 0.3
    else:  # bend: torso forward and sideways on straight legs
        p[INDEX["abdomen_y"]] = -1.2 * s
        p[INDEX["abdomen_x"]] = rng.uniform(-0.5, 0.5)
        p[INDEX["abdomen_z"]] = rng.uniform(-0.6, 0.6)
        for side in ("right", "left"):
            legs(p, side, -0.5 * s, -0.1, 0.1)
    arms(p, rng, rng.random(), rng.random())
    for side in ("right", "left"):
        p[INDEX[side + "_hip_x"]] += rng.gauss(-0.1, 0.08)
        p[INDEX[side + "_hip_z"]] += rng.gauss(0, 0.12)
        p[INDEX[side + "_ankle_x"]] += rng.gauss(0, 0.15)
    p = [min(max(v + rng.gauss(0, 0.03), lo), hi) for v, (_, lo, hi) in zip(p, JOINTS)]
    return [round(v, 4) for v in p]


def condition(p):
    h = 0.0
    for side in ("right", "left"):
        hip, knee = p[INDEX[side + "_hip_y"]], p[INDEX[side + "_knee"]]
        h += 0.5 * (0.08 + 0.42 * (math.cos(hip) + math.cos(hip - knee)))
    return [round(h, 4), p[INDEX["abdomen_y"]], p[INDEX["abdomen_x"]]]


def main():
    rng = random.Random(20211)
    poses = [pose(rng) for _ in range(1000)]
    print(json.dumps({
        "description": "Podium's authored pose set for the 21-hinge humanoid (get-up seed Table 2); "
                       "see make_humanoid21_poses.py",
        "dof_names": [n for n, _, _ in JOINTS],
        "lower": [lo for _, lo, _ in JOINTS],
        "upper": [hi for _, _, hi in JOINTS],
        "condition_names": ["pelvis_height_m", "torso_pitch_rad", "torso_roll_rad"],
        "poses": poses,
        "conditions": [condition(p) for p in poses],
    }, separators=(",", ":")))


if __name__ == "__main__":
    main()
