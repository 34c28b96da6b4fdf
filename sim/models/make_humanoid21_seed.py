#!/usr/bin/env python3
"""Derives humanoid21_seed.json, the get-up task's body, from humanoid21.json (standard library only).

humanoid21 already carries the seed repository's passive joint damping and stiffness (applied when a
World sets passive_joints). The seed's MuJoCo body (tianxintao/get_up_control data/humanoid_static.xml,
the `body` default class) also gives every hinge armature 0.01 and its body geoms condim 1, which
makes contacts between two of its bodies frictionless (the floor's condim 3 wins against a body, so
body-floor contacts keep friction). This script adds both; edit it, not the JSON.

Run from the repository root: python3 sim/models/make_humanoid21_seed.py
"""
import json
import pathlib

HERE = pathlib.Path(__file__).resolve().parent
ARMATURE = 0.01  # humanoid_static.xml, <default class="body"><joint ... armature=".01">


def main():
    model = json.loads((HERE / "humanoid21.json").read_text())
    model["name"] = "humanoid21_seed"
    base = model["source"].replace("; its armature 0.01 is not modelled.", ".")
    model["source"] = (
        "humanoid21 (its source: " + base + ") with the rest of the seed repository's joint and contact "
        "model (tianxintao/get_up_control data/humanoid_static.xml, default class body): armature 0.01 kg·m² on "
        "every hinge, and frictionless contacts between the character's own bodies (condim 1). Derived by "
        "make_humanoid21_seed.py."
    )
    model["self_contact_friction"] = 0.0
    for body in model["bodies"]:
        for joint in body.get("joints", []):
            joint["armature"] = ARMATURE
    (HERE / "humanoid21_seed.json").write_text(json.dumps(model, indent=1) + "\n")


if __name__ == "__main__":
    main()
