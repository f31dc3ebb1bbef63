# DOE of section 4.2: RW_max of each test, RW_C, the global index per test (shards), effects.
from cdpr.jobs import doe_tests

DOE = STUDY["doe"]
DOE_TESTS = doe_tests(STUDY).set_index("test")  # Table 2: number -> kind, h_m, r_p_m
TESTS = list(DOE_TESTS.index)


def test_args(test):
    """Overrides of DOE test `test` (Table 2)."""
    return pulley_args(DOE_TESTS.loc[int(test)].to_dict())


rule workspace_grid:
    input:
        robot=ROBOTS[DOE["robot"]],
    output:
        f"{RES}/shards/workspace/test{{test}}.parquet",
    params:
        design=lambda w: test_args(int(w.test)),
    log:
        f"{RES}/logs/workspace_test{{test}}.log",
    threads: SOLVER_THREADS
    shell:
        "{CDPR} grid --threads {threads} --robot {input.robot} {params.design} --frame --n {DOE[workspace_n]} --out {output} > {log} 2>&1"


rule regular_workspace:
    input:
        expand(f"{RES}/shards/workspace/test{{test}}.parquet", test=TESTS),
    output:
        f"{RES}/doe/rw_max.csv",
        f"{RES}/doe/rw_c.json",
    shell:
        "{CDPR} job rw --study {STUDY_FILE} --inputs {input} --outputs {output}"


rule index_shard:
    input:
        robot=ROBOTS[DOE["robot"]],
        box=f"{RES}/doe/rw_c.json",
    output:
        f"{RES}/shards/doe/test{{test}}_{{shard}}.parquet",
    params:
        design=lambda w: test_args(int(w.test)),
    log:
        f"{RES}/logs/doe_test{{test}}_{{shard}}.log",
    threads: SOLVER_THREADS
    shell:
        "{CDPR} grid --threads {threads} --robot {input.robot} {params.design} --box-file {input.box} --n {DOE[index_n]}"
        " --shard {wildcards.shard} --shards {DOE[shards]} --out {output} > {log} 2>&1"


rule doe:
    input:
        [f"{RES}/shards/doe/test{t}_{s}.parquet" for t in TESTS for s in range(DOE["shards"])],
    output:
        f"{RES}/doe/doe.csv",
        f"{RES}/doe/effects.csv",
        report(f"{RES}/doe/responses.png", caption="../report/doe.rst", category="DOE"),
        report(f"{RES}/doe/effects.png", caption="../report/effects.rst", category="DOE"),
    shell:
        "{CDPR} job doe --study {STUDY_FILE} --shards {DOE[shards]} --inputs {input} --outputs {output}"
