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
for _key, _path in ROBOTS.items():
    _robot = yaml.safe_load(open(_path))
    if not isinstance(_robot, dict) or not isinstance(_robot.get("cables"), list):
        raise WorkflowError(f"{STUDY_FILE}: key 'robots.{_key}': {_path} is not a robot file with a 'cables' list")
# robots with more cables than degrees of freedom: the subset map (Fig. 9) applies to them
REDUNDANT = [k for k, p in ROBOTS.items() if len(yaml.safe_load(open(p))["cables"]) > 3]
for _sec in ("trajectories",):
    for _key in STUDY[_sec]["paths"]:
        if _key not in ROBOTS:
            raise WorkflowError(f"{STUDY_FILE}: key '{_sec}.paths.{_key}': unknown robot; allowed: {', '.join(ROBOTS)}")
if STUDY["doe"]["robot"] not in ROBOTS:
    raise WorkflowError(f"{STUDY_FILE}: key 'doe.robot': unknown robot {STUDY['doe']['robot']!r}; allowed: {', '.join(ROBOTS)}")
PULLEYS = STUDY["pulleys"]
# threads of one solver job (the compiled engine runs points in parallel); many small jobs: use 1
SOLVER_THREADS = STUDY.get("solver_threads", 2)


wildcard_constraints:
    robot="|".join(ROBOTS),
    pulley="|".join(PULLEYS),


def pulley_args(p, E=None):
    """Command-line overrides for a pulley design {kind, h_m, r_p_m} (same as editing the robot
    file), with the study's dead length and solver, and optionally E [Pa]."""
    args = f"--pulley {p['kind']} --dead-length {STUDY['dead_length_m']} --method {STUDY['solver']}"
    if p["kind"] != "fixed":
        args += f" --h {p.get('h_m', 0)} --rp {p.get('r_p_m', 0)}"
    return args if E is None else f"{args} --E {E}"


def design_args(pulley):
    """Overrides for the pulley design labelled `pulley` in the study."""
    return pulley_args(PULLEYS[pulley])


def all_targets():
    t = [f"{RES}/winch/winch.csv", f"{RES}/winch/winch.png"]
    t += expand(f"{RES}/plane/{{robot}}_{{pulley}}.png", robot=ROBOTS, pulley=PULLEYS)
    t += expand(f"{RES}/plane/{{robot}}_{{pulley}}_subsets.png", robot=REDUNDANT, pulley=PULLEYS)
    t += [f"{RES}/trajectories/trajectories.png"]
    t += [f"{RES}/volumes/volumes.csv"] + expand(f"{RES}/volumes/{{label}}_VL.png", label=VOL_LABELS)
    t += [f"{RES}/doe/doe.csv", f"{RES}/maps/lines.csv", f"{RES}/elasticity/bands.csv", f"{RES}/dead_length/dead_length.csv"]
    t += [f"{RES}/summary.md", f"{RES}/summary.csv"]
    return t
