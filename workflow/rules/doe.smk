# DOE of Paty 2021 section 4.2: RW_max of each test, RW_C, the global index per test (shards), effects.
rule workspace_grid:
    input:
        robot=DOE_ROBOT,
    output:
        table=f"{RES}/shards/workspace/test{{test}}.parquet",
    params:
        design=lambda w: test_args(int(w.test)),
        n=DOE["workspace_n"],
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/workspace_test{{test}}.log",
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} grid --threads {threads} --robot {input.robot} {params.design} --frame --n {params.n} --out {output.table} > {log} 2>&1"


rule regular_workspace:
    input:
        tables=expand(f"{RES}/shards/workspace/test{{test}}.parquet", test=TESTS),
        robot=DOE_ROBOT,
    output:
        table=f"{RES}/doe/rw_max.csv",
        json=f"{RES}/doe/rw_c.json",
    params:
        study=uses("doe", "dead_length_m"),
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/regular_workspace.log",
    shell:
        "{params.cdpr} job rw --study {params.study_file} --tables {input.tables} --table {output.table} --json {output.json} > {log} 2>&1"


rule index_shard:
    input:
        robot=DOE_ROBOT,
        box=rules.regular_workspace.output.json,
    output:
        table=f"{RES}/shards/doe/test{{test}}_{{shard}}.parquet",
    params:
        design=lambda w: test_args(int(w.test)),
        n=DOE["index_n"],
        shards=DOE["shards"],
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/doe_test{{test}}_{{shard}}.log",
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} grid --threads {threads} --robot {input.robot} {params.design} --box-file {input.box} --n {params.n}"
        " --shard {wildcards.shard} --shards {params.shards} --out {output.table} > {log} 2>&1"


rule doe:
    input:
        tables=[f"{RES}/shards/doe/test{t}_{s}.parquet" for t in TESTS for s in range(DOE["shards"])],
    output:
        table=f"{RES}/doe/doe.csv",
        effects=f"{RES}/doe/effects.csv",
        figure=report(f"{RES}/doe/responses.png", caption="../report/doe.rst", category="DOE"),
        pdf=f"{RES}/doe/responses.pdf",
        effects_figure=report(f"{RES}/doe/effects.png", caption="../report/effects.rst", category="DOE"),
        effects_pdf=f"{RES}/doe/effects.pdf",
    params:
        study=uses("doe"),
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/doe.log",
    shell:
        "{params.cdpr} job doe --study {params.study_file} --tables {input.tables} --table {output.table} --effects {output.effects}"
        " --figure {output.figure} --effects-figure {output.effects_figure} > {log} 2>&1"
