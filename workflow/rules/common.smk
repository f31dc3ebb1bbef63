# Study configuration, validation and helpers shared by the rules.
#
# The study file is read and validated ONCE here, by the library (cdpr.pipeline.study.load_study: the JSON
# schema cdpr/schemas/study.schema.yaml, then every check a schema cannot make, robot files
# included), so that a bad value stops the run before any job with one sentence naming the study
# file and the key. Every rule declares as `params` the study values its job reads and COMMON (the
# command, the study file and the library's code version CODE), so that Snakemake reruns exactly the
# jobs an edit affects. Every output and input path comes from cdpr.pipeline.results (LAYOUT).
import hashlib
import importlib.resources
import shlex
import sys
from pathlib import Path

from cdpr.errors import CdprError
from cdpr.pipeline.results import Layout
from cdpr.pipeline.study import check_results_folder, load_study, path_robot

STUDY_FILE = config["study"]
try:
    STUDY = load_study(STUDY_FILE)
    check_results_folder(config["results"])
except CdprError as exc:
    raise WorkflowError(f"invalid study configuration: {exc}")
RES = config["results"]
# every path of the results folder (cdpr.pipeline.results)
LAYOUT = Layout(STUDY, RES)
# the interpreter quoted: the pipeline runs from a folder whose path has spaces or non-ASCII letters
CDPR = f"{shlex.quote(sys.executable)} -m cdpr"
# the papers' numbers, shipped with the library (an input of the rules that read them)
PAPER_VALUES = str(importlib.resources.files("cdpr") / "data" / "paper_values.yaml")
ROBOTS = dict(STUDY["robots"])
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


def common(study_file=STUDY_FILE, **more):
    """The params every rule that runs the library declares: its command, the study file it reads
    (the pipeline's study; a comparison or calibration rule names its own) and the code version,
    with ``more`` (the comparison file ...)."""
    return {"cdpr": CDPR, "study_file": study_file, "code": CODE, **more}


# the params of every rule of the pipeline's study
COMMON = common()
# the end of every shell command: the job's output and errors go to its log, and when the job fails
# the log's last line (the library's one-line error) reaches the console too, with the exit status
TO_LOG = (
    " > {log:q} 2>&1 || {{ s=$?; echo \"job failed (exit status $s): $(tail -n 1 {log:q})\" >&2; exit $s; }}"
)


def outputs(rule, **reports):
    """The outputs of `rule` (cdpr.pipeline.results); name=(caption, category) puts a figure in the
    Snakemake report."""
    out = LAYOUT.outputs(rule)
    for name, (caption, category) in reports.items():
        out[name] = report(out[name], caption=caption, category=category)
    return out


def uses(*keys):
    """The study values a job reads, as a param (a change of any of them reruns the job).

    A key ``"section.sub"`` is the one value ``sub`` of the section (``"volumes.n"``): a job that
    reads part of a section does not rerun when another part of it changes."""
    out = {}
    for k in keys:
        section, _, sub = k.partition(".")
        out[k] = (STUDY.get(section) or {}).get(sub) if sub else STUDY.get(section)
    return out


wildcard_constraints:
    robot="|".join(ROBOTS),
    pulley="|".join(PULLEYS),
    path="|".join(STUDY["trajectories"]["paths"]),


# Sections of the study used by several rule files.
DOE = STUDY["doe"]
DOE_ROBOT = ROBOTS[DOE["robot"]]
OPT = STUDY["optimal"]


def uq_uses(*keys):
    """The part of the study's uncertainty section a job reads (a change of it reruns the job)."""
    return {k: (STUDY.get("uncertainty") or {}).get(k) for k in keys}


def all_targets():
    """Every file the study writes (cdpr.pipeline.results): a missing one, intermediate or not, is rebuilt."""
    return LAYOUT.targets()
