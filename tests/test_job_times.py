"""benchmarks/job_times.py pairs Snakemake's job starts and ends from its log (issue 19)."""

import importlib.util

from tests.conftest import ROOT

LOG = """Building DAG of jobs...
  Command: .venv/bin/snakemake --cores 2 reproduce_paper
[Wed Dec  2 14:57:51 2026]
localrule winch_table:
    output: r/winch/winch.csv
    jobid: 1
[Wed Dec  2 14:57:52 2026]
rule plane_table:
    jobid: 2
[Wed Dec  2 14:57:54 2026]
Finished jobid: 1 (Rule: winch_table)
[Wed Dec  2 14:57:54 2026]
rule plane_table:
    jobid: 3
[Wed Dec  2 14:58:00 2026]
Finished jobid: 2 (Rule: plane_table)
[Wed Dec  2 14:58:04 2026]
Finished jobid: 3 (Rule: plane_table)
[Wed Dec  2 14:58:05 2026]
rule never_finished:
    jobid: 4
"""


def _module():
    spec = importlib.util.spec_from_file_location("job_times", ROOT / "benchmarks" / "job_times.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_jobs_are_paired_by_jobid_and_summed_per_rule(tmp_path):
    path = tmp_path / "run.snakemake.log"
    path.write_text(LOG, encoding="utf-8")
    mod = _module()
    jobs, command, first, last = mod.parse(path)
    assert command == ".venv/bin/snakemake --cores 2 reproduce_paper"
    assert (last - first).total_seconds() == 14
    # side by side: plane_table 2 runs 14:57:52-14:58:00 (8 s) while jobs 1 and 3 run; a job that
    # never finished is not counted
    assert mod.table(jobs) == [("plane_table", 2, 18.0, 10.0), ("winch_table", 1, 3.0, 3.0)]
