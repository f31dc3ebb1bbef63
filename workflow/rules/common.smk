# Study configuration, validation and helpers shared by the rules.
import sys

import yaml
from snakemake.utils import validate

STUDY_FILE = config["study"]
with open(STUDY_FILE) as fh:
    STUDY = yaml.safe_load(fh)
try:
    validate(STUDY, "../schemas/study.schema.yaml")
except Exception as exc:  # the schema error, prefixed with the file it came from
    raise WorkflowError(f"{STUDY_FILE}: invalid study configuration: {exc}")
RES = config["results"]
CDPR = f"{sys.executable} -m cdpr"
ROBOTS = STUDY["robots"]
PULLEYS = STUDY["pulleys"]


wildcard_constraints:
    robot="|".join(ROBOTS),
    pulley="|".join(PULLEYS),


def design_args(pulley):
    """Command-line overrides for a pulley design of the study (same as editing the robot file)."""
    p = PULLEYS[pulley]
    args = f"--pulley {p['kind']} --dead-length {STUDY['dead_length_m']}"
    if p["kind"] != "fixed":
        args += f" --h {p.get('h_m', 0)} --rp {p.get('r_p_m', 0)}"
    return args + f" --method {STUDY['solver']}"


def all_targets():
    t = [f"{RES}/winch/winch.csv", f"{RES}/winch/winch.png"]
    t += expand(f"{RES}/plane/{{robot}}_{{pulley}}.png", robot=ROBOTS, pulley=PULLEYS)
    t += expand(f"{RES}/plane/{{robot}}_{{pulley}}_subsets.png", robot=[r for r in ROBOTS if r != "CDPR3"], pulley=PULLEYS)
    t += [f"{RES}/trajectories/trajectories.png"]
    t += [f"{RES}/volumes/volumes.csv"] + expand(f"{RES}/volumes/{{label}}_VL.png", label=VOL_LABELS)
    t += [f"{RES}/doe/doe.csv", f"{RES}/maps/lines.csv", f"{RES}/elasticity/bands.csv", f"{RES}/dead_length/dead_length.csv"]
    t += [f"{RES}/summary.md", f"{RES}/summary.csv"]
    return t
