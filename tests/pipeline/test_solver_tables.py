"""The solver jobs of a study (``cdpr.pipeline.solver_tables``) take the design and the solver options
from the study as values and write the table the public command writes with the same options, byte
for byte: what the Snakemake rules ran before they passed values instead of command-line text."""

from pathlib import Path

import pytest

from cdpr.cli.main import main
from cdpr.errors import CdprError
from cdpr.pipeline import solver_tables, study

ROOT = Path(__file__).resolve().parents[2]


def _args(st, spec, E=None):
    """The command-line text of the design and solver options (what workflow/rules passed before)."""
    args = ["--pulley", spec["kind"], "--dead-length", str(st["dead_length_m"]), "--method", st["solver"]]
    args += ["--redundancy", st.options.redundancy, "--threads", "1"]
    if st.options.rotvec is not None:
        args += ["--rotvec", *(repr(float(x)) for x in st.options.rotvec)]
    if spec["kind"] != "fixed":
        args += ["--h", str(spec.get("h_m", 0)), "--rp", str(spec.get("r_p_m", 0))]
    return args + ([] if E is None else ["--E", E])


def _same(a, b):
    assert Path(a).read_bytes() == Path(b).read_bytes()


@pytest.mark.parametrize("name", ["quick.yaml", "quick_physical.yaml"])
def test_plane_and_path_jobs_write_the_command_line_tables(name, tmp_path, capsys):
    st = study.load_study(ROOT / "config" / "studies" / name)
    robot_key, pulley = next(iter(st["robots"])), "DR"
    spec = st["pulleys"][pulley]
    job = tmp_path / "job.csv"
    solver_tables.plane_table(st, robot_key, pulley, job, threads=1)
    cli = tmp_path / "cli.csv"
    p = st["plane"]
    main(
        [
            "plane",
            "--robot",
            st["robots"][robot_key],
            *_args(st, spec),
            "--z",
            str(p["z_m"]),
            "--n",
            str(p["n"]),
            "--out",
            str(cli),
        ]
    )
    _same(job, cli)
    label = next(iter(st["trajectories"]["paths"]))
    path = st["trajectories"]["paths"][label]
    solver_tables.trajectory_table(st, label, pulley, job, threads=1)
    main(
        ["trajectory", "--robot", st["robots"][study.path_robot(st, label)], *_args(st, spec)]
        + ["--start", *map(str, path["start_m"]), "--end", *map(str, path["end_m"])]
        + ["--n", str(st["trajectories"]["points"]), "--out", str(cli)]
    )
    _same(job, cli)


def test_grid_jobs_write_the_command_line_tables(tmp_path):
    st = study.load_study(ROOT / "config" / "studies" / "quick.yaml")
    robot_key, pulley = st["doe"]["robot"], "SR"
    job, cli = tmp_path / "job.parquet", tmp_path / "cli.parquet"
    v = st["volumes"]
    solver_tables.volume_shard(st, robot_key, pulley, 1, job, threads=1)
    main(
        ["grid", "--robot", st["robots"][robot_key], *_args(st, st["pulleys"][pulley]), "--frame"]
        + ["--n", str(v["n"]), "--shard", "1", "--shards", str(v["shards"]), "--out", str(cli)]
    )
    _same(job, cli)
    test = study.doe_tests(st).set_index("test").loc[3].to_dict()
    solver_tables.workspace_grid(st, 3, job, threads=1)
    main(
        ["grid", "--robot", st["robots"][robot_key], *_args(st, test), "--frame"]
        + ["--n", str(st["doe"]["workspace_n"]), "--out", str(cli)]
    )
    _same(job, cli)


def test_the_elasticity_path_takes_the_study_modulus_not_its_label(tmp_path):
    """The file name's label of E is .6g text; the job looks the study's value up by it. A modulus
    with more digits than the label would have been solved at the rounded value when the label was
    passed as --E."""
    st = study.load_study(ROOT / "config" / "studies" / "quick.yaml")
    st["elasticity"]["E_path_Pa"] = [102.21234567e9]
    label = f"{102.21234567e9:.6g}"
    seen = {}
    real = study.design_robot

    def spy(st_, key, spec, E=None, dead_length=None):
        seen["E"] = E
        return real(st_, key, spec, E=E, dead_length=dead_length)

    try:
        study.design_robot = spy
        solver_tables.elasticity_path(st, next(iter(st["optimal"])), label, tmp_path / "p.csv", threads=1)
    finally:
        study.design_robot = real
    assert seen["E"] == 102.21234567e9 != float(label)
    with pytest.raises(CdprError, match="--modulus 1e11 is none of elasticity.E_path_Pa"):
        solver_tables.elasticity_path(st, next(iter(st["optimal"])), "1e11", tmp_path / "p.csv")


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda st, t: solver_tables.plane_table(st, "CDPR4", "XX", t), "no pulley design 'XX' in pulleys"),
        (lambda st, t: solver_tables.trajectory_table(st, "nowhere", "SR", t), "no path 'nowhere'"),
        (lambda st, t: solver_tables.workspace_grid(st, 9, t), "no DOE test 9"),
        (
            lambda st, t: solver_tables.elasticity_path(st, "nodesign", "1.022e+11", t),
            "no design 'nodesign' in optimal",
        ),
    ],
)
def test_a_label_the_study_lacks_is_one_line(call, match, tmp_path):
    st = study.load_study(ROOT / "config" / "studies" / "quick.yaml")
    with pytest.raises(CdprError, match=match):
        call(st, tmp_path / "t.csv")
