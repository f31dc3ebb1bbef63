"""End to end on a user's own design: config/studies/example.yaml (the robot of
config/robots/example_8x6x4.yaml) through the whole study, in a working folder under pytest's
temporary folder (tests/quick_runs.py). A module of its own: make test runs it on one pytest-xdist
worker while the quick runs use the other (tests/conftest.py)."""

import pandas as pd

from tests.quick_runs import make_workdir, snakemake


def test_own_design_end_to_end(tmp_path):
    work = make_workdir(tmp_path / "w")
    out = tmp_path / "example"
    p = snakemake("reproduce_paper", "study=studies/example.yaml", f"results={out}", cwd=work)
    assert p.returncode == 0, p.stderr[-3000:]
    doe = pd.read_csv(out / "doe" / "doe.csv")
    assert len(doe) == 8 and doe.index_m.notna().all() and (doe.index_m > 0).all()
    plane = pd.read_csv(out / "plane" / "FRAME_DR50.csv")
    assert (plane.status == "ok").mean() > 0.8
    text = (out / "summary.md").read_text()
    assert (
        "not scored" in text and "not reproduced" not in text
    )  # an own design is not scored against the paper
