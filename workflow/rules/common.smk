# Study configuration, validation and helpers shared by the rules.
#
# The study file is read and validated ONCE here, by the library (cdpr.pipeline.study.load_study: the JSON
# schema cdpr/schemas/study.schema.yaml, then every check a schema cannot make, robot files
# included), so that a bad value stops the run before any job with one sentence naming the study
# file and the key. Every rule declares as `params` the study values its job reads and the
# library's code version (CODE), so that Snakemake reruns exactly the jobs an edit affects.
import hashlib
import sys
from pathlib import Path

from cdpr.errors import CdprError
from cdpr.pipeline.study import doe_tests, E_values, load_study, map_kinds

STUDY_FILE = config["study"]
try:
    STUDY = load_study(STUDY_FILE)
except CdprError as exc:
    raise WorkflowError(f"invalid study configuration: {exc}")
RES = config["results"]
CDPR = f"{sys.executable} -m cdpr"
ROBOTS = dict(STUDY["robots"])
# robots with more cables than degrees of freedom: the subset map (Fig. 9) applies to them
REDUNDANT = [k for k, robot in STUDY.robot_models.items() if robot.m > 3]
PULLEYS = STUDY["pulleys"]
# threads of one solver job (the compiled engine runs points in parallel); many small jobs: use 1
SOLVER_THREADS = STUDY.get("solver_threads", 2)


def _code_version():
    """Version and a hash of the library's sources and schemas: a param of every rule that runs
    the library, so that a change of the physics reruns the jobs (Snakemake does not see imports)."""
    import cdpr

    root = Path(cdpr.__file__).parent
    h = hashlib.sha256()
    for f in sorted(f for pat in ("**/*.py", "**/*.yaml") for f in root.glob(pat)):
        h.update(f.relative_to(root).as_posix().encode() + f.read_bytes())
    return f"{cdpr.__version__}+{h.hexdigest()[:16]}"


CODE = _code_version()


def uses(*keys):
    """The study values a job reads, as a param (a change of any of them reruns the job)."""
    return {k: STUDY.get(k) for k in keys}


wildcard_constraints:
    robot="|".join(ROBOTS),
    pulley="|".join(PULLEYS),


# paper: the 3-of-4 subset rule; physical: the equilibrium on all cables (every solver job gets it)
REDUNDANCY = STUDY["redundancy"]


def pulley_args(p, E=None):
    """Command-line overrides for a pulley design {kind, h_m, r_p_m} (same as editing the robot
    file), with the study's dead length, solver and redundancy mode, and optionally E [Pa]."""
    args = f"--pulley {p['kind']} --dead-length {STUDY['dead_length_m']} --method {STUDY['solver']}"
    args += f" --redundancy {REDUNDANCY}"
    if p["kind"] != "fixed":
        args += f" --h {p.get('h_m', 0)} --rp {p.get('r_p_m', 0)}"
    return args if E is None else f"{args} --E {E}"


# Sections of the study used by several rule files.
PATHS = STUDY["trajectories"]["paths"]
VOL = STUDY["volumes"]
VOL_LABELS = expand("{robot}_{pulley}", robot=ROBOTS, pulley=PULLEYS)
DOE = STUDY["doe"]
DOE_TESTS = doe_tests(STUDY).set_index("test")  # Table 2: number -> kind, h_m, r_p_m
TESTS = list(DOE_TESTS.index)
DOE_ROBOT = ROBOTS[DOE["robot"]]
EL = STUDY["elasticity"]
OPT = STUDY["optimal"]
E_VALUES = [f"{e:.6g}" for e in E_values(STUDY)]
E_PATH = [f"{float(e):.6g}" for e in EL["E_path_Pa"]]


def uq_uses(*keys):
    """The part of the study's uncertainty section a job reads (a change of it reruns the job)."""
    return {k: (STUDY.get("uncertainty") or {}).get(k) for k in keys}


def test_args(test):
    """Overrides of DOE test `test` (Table 2)."""
    return pulley_args(DOE_TESTS.loc[int(test)].to_dict())


def volume_shards(label):
    """The solver shards of one robot_pulley label (volumes)."""
    return expand(f"{RES}/shards/volume/{label}_{{shard}}.parquet", shard=range(VOL["shards"]))


def all_targets():
    t = [f"{RES}/winch/winch.csv", f"{RES}/winch/winch.png"]
    t += expand(f"{RES}/plane/{{robot}}.png", robot=ROBOTS)
    t += expand(f"{RES}/plane/{{robot}}_subsets.png", robot=REDUNDANT)
    t += [f"{RES}/trajectories/trajectories.png"]
    t += [f"{RES}/volumes/volumes.csv"] + expand(f"{RES}/volumes/{{label}}_VL.png", label=VOL_LABELS)
    t += [f"{RES}/doe/doe.csv", f"{RES}/maps/lines.csv", f"{RES}/elasticity/bands.csv", f"{RES}/dead_length/dead_length.csv"]
    if STUDY.get("uncertainty"):
        t += [f"{RES}/uncertainty/bands.csv"]
    t += [f"{RES}/summary.md", f"{RES}/summary.csv"]
    return t
