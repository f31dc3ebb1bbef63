"""Write the HP4 sample tables in cdpr's motor-angle data contract (docs/hangprinter.md).

    .venv/bin/python data/hangprinter/make_cdpr_tables.py

For each HP4 set ``NAME_samples.csv`` (the neutral extraction, README.md) it writes ``NAME_cdpr.csv``
with the columns ``sample, motor_deg_1..4, [force_N_1..4,] x_m, y_m, z_m``: cable i = anchor A, B,
C, D; the motor angles as read; the forces where recorded (the eff69f9 alignment, README.md); the
positions in metres where the set gives one (x_mm, y_mm, z_mm: the positions the author trusts),
empty elsewhere. For HP3 (line lengths in mm, no position) it writes ``hp3_2018_cdpr.csv`` (the
line change in mm as the motor angle in degrees), ``robot_hp3_2018.yaml`` (the hand-measured
anchors with the identity spool) and ``tool_hp3_2018.yaml`` (the tool's HP3 anchors); for each
HP4 set the tool's solution as ``tool_NAME.yaml``. Deterministic: the same input gives the same
bytes.
"""

import json
import math
from pathlib import Path

import pandas as pd

HERE = Path(__file__).resolve().parent
SETS = ("hp4_2022_force_series2", "hp4_2021_12_grid")


def table(name):
    src = pd.read_csv(HERE / f"{name}_samples.csv")
    out = pd.DataFrame({"sample": src["sample"]})
    for i, a in enumerate("ABCD", start=1):
        out[f"motor_deg_{i}"] = src[f"motor_{a}_deg"]
    if src[[f"force_{a}_N" for a in "ABCD"]].notna().any().any():
        for i, a in enumerate("ABCD", start=1):
            out[f"force_N_{i}"] = src[f"force_{a}_N"]
    for c in "xyz":
        out[f"{c}_m"] = src[f"{c}_mm"] / 1000.0
    return out


if __name__ == "__main__":
    for name in SETS:
        path = HERE / f"{name}_cdpr.csv"
        table(name).to_csv(path, index=False, float_format="%.12g", lineterminator="\n")
        print(f"wrote {path.relative_to(HERE.parent.parent)}")


#: The community tool's published solutions (README.md's table: anchors [mm], spool radii R [mm],
#: buildup factor Q [mm]) as robot files over config/robots/hangprinter_hp4.yaml, to score with
#: ``cdpr calibrate cv --fixed``.
TOOL = {
    "hp4_2022_force_series2": {
        "anchors": [
            [16.83, -1584.86, -113.17],
            [1290.18, 1229.19, -157.45],
            [-1409.88, 742.61, -151.80],
            [21.85, -0.16, 2343.67],
        ],
        "R": [76.017, 76.017, 76.017, 75.657],
        "Q": 0.06875,
        "version": "hp_mark_adjusted, 790dca2 (SLSQP)",
    },
    "hp4_2021_12_grid": {
        "anchors": [
            [14.33, -1621.46, -125.47],
            [1319.48, 1251.48, -175.61],
            [-1422.98, 743.22, -152.34],
            [23.79, 3.19, 2339.33],
        ],
        "R": [75.774, 75.849, 75.519, 75.648],
        "Q": 0.05,
        "version": "6a417f4 (SLSQP)",
    },
}


def tool_robot(name):
    import yaml

    doc = yaml.safe_load((HERE.parent.parent / "config/robots/hangprinter_hp4.yaml").read_text())
    t = TOOL[name]
    doc["name"] = f"HP4 ({name}: the Hangprinter tool's solution)"
    doc["description"] = f"the community calibration tool's published solution for {name}, {t['version']}"
    for c, a, r in zip(doc["cables"], t["anchors"], t["R"]):
        c["A_m"] = [round(x / 1000.0, 8) for x in a]
        c["winch"]["spool_radius_m"] = round(r / 1000.0, 9)
        c["winch"]["buildup_factor_m"] = round(t["Q"] / 1000.0, 12)
    head = (
        f"# The Hangprinter tool's own solution for data/hangprinter/{name} ({t['version']}; README.md),\n"
        "# over config/robots/hangprinter_hp4.yaml (machine constants, dead lengths, line stiffness).\n"
        "# Written by data/hangprinter/make_cdpr_tables.py.\n"
    )
    return head + yaml.safe_dump(doc, sort_keys=False)


#: HP3 (2018) reports line lengths in mm, with no spool model and no measured position. In cdpr's
#: motor-angle contract a line change in mm is a "motor angle" in degrees through the identity spool:
#: U = 1, O = 1, L = H = 1, Q = 0 and r0 = 180/pi mm, so that s = r0 phi = theta mm exactly.
HP3 = "hp3_2018"
IDENTITY_R0_M = 0.18 / math.pi


def hp3_table():
    src = pd.read_csv(HERE / f"{HP3}_samples.csv")
    out = pd.DataFrame({"sample": src["sample"]})
    for i, a in enumerate("ABCD", start=1):
        out[f"motor_deg_{i}"] = src[f"dline_{a}_mm"]
    for c in "xyz":
        out[f"{c}_m"] = src[f"{c}_mm"] / 1000.0  # all empty: no position was measured
    return out


#: The community tool's HP3 solution (README.md's table: 1df0762, mystic; its gauge A_x = D_x = D_y = 0).
HP3_TOOL = {
    "anchors": [
        [0.0, -1113.06, -104.52],
        [998.67, 575.99, -129.59],
        [-972.16, 545.72, -104.37],
        [0.0, 0.0, 2728.76],
    ],
    "version": "1df0762 (mystic)",
}


def hp3_robot(anchors_mm=None, what=None):
    """HP3 as a robot file: the hand-measured anchors of the JSON, fixed anchors, the identity spool
    (one degree = one mm of line; HP3's firmware converted its steps to mm itself). Mass and line
    stiffness are placeholders: the rigid-line model (``--model standard``) does not use them."""
    import yaml

    meta = json.loads((HERE / f"{HP3}.json").read_text())
    anchors_mm = meta["hand_anchors_mm"] if anchors_mm is None else anchors_mm
    doc = {
        "name": "HP3 (2018)" if what is None else f"HP3 (2018: {what})",
        "description": f"Hangprinter v3, {what or 'hand-measured anchors'}; line lengths in mm through the identity spool",
        "platform": {"mass_kg": 1.0, "gravity_m_per_s2": 9.81},
        "cable": {"young_modulus_Pa": 1.0e11, "diameter_m": 0.0005, "max_tension_N": 70.0},
        "pulley": {"kind": "fixed"},
        "winch": {"kind": "spool", "buildup_factor_m": 0.0},
        "cables": [
            {
                "A_m": [round(x / 1000.0, 8) for x in a],
                "dead_length_m": 0.0,
                "winch": {
                    "spool_radius_m": IDENTITY_R0_M,
                    "mechanical_advantage": 1,
                    "lines_per_spool": 1,
                    "motor_gear_teeth": 1,
                    "spool_gear_teeth": 1,
                },
            }
            for a in anchors_mm
        ],
    }
    src = f"{HP3}.json: hand_anchors_mm" if what is None else f"README.md: {what}"
    head = (
        f"# HP3 (data/hangprinter/{src}) for its line lengths in mm: the identity\n"
        "# spool (r0 = 180/pi mm, U = O = L = H = 1, Q = 0) makes a line change of x mm a motor angle of x deg.\n"
        "# Written by data/hangprinter/make_cdpr_tables.py.\n"
    )
    return head + yaml.safe_dump(doc, sort_keys=False)


if __name__ == "__main__":
    for name in TOOL:
        path = HERE / f"tool_{name}.yaml"
        path.write_text(tool_robot(name))
        print(f"wrote {path.relative_to(HERE.parent.parent)}")
    path = HERE / f"{HP3}_cdpr.csv"
    hp3_table().to_csv(path, index=False, float_format="%.12g", lineterminator="\n")
    print(f"wrote {path.relative_to(HERE.parent.parent)}")
    path = HERE / f"robot_{HP3}.yaml"
    path.write_text(hp3_robot())
    print(f"wrote {path.relative_to(HERE.parent.parent)}")
    path = HERE / f"tool_{HP3}.yaml"
    path.write_text(hp3_robot(HP3_TOOL["anchors"], f"the Hangprinter tool's solution, {HP3_TOOL['version']}"))
    print(f"wrote {path.relative_to(HERE.parent.parent)}")
