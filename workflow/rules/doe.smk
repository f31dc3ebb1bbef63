# DOE of Paty 2021 section 4.2: RW_max of each test, RW_C, the global index of the tests (shards of them), effects.
rule workspace_grid:
    input:
        robot=DOE_ROBOT,
    output:
        **outputs("workspace_grid"),
    params:
        **COMMON,
        # a spatial robot's workspace is the wrench-feasible one (tensions in [t_min, T_a] hold the pose)
        study=uses("doe.robot", "doe.levels", "doe.workspace_n", "dead_length_m", "solver", "redundancy", "rotvec_rad", "wrench"),
    log:
        LAYOUT.log("workspace_grid"),
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job workspace-grid --threads {threads} --study {params.study_file:q} --test {wildcards.test}"
        " --table {output.table:q}" + TO_LOG


rule regular_workspace:
    input:
        tables=LAYOUT.paths("workspace_grid", "table"),
        robot=DOE_ROBOT,
    output:
        **outputs("regular_workspace"),
    params:
        **COMMON,
        study=uses("doe", "dead_length_m", "wrench"),
    log:
        LAYOUT.log("regular_workspace"),
    shell:
        "{params.cdpr} job rw --study {params.study_file:q} --tables {input.tables:q} --table {output.table:q}"
        " --json {output.json:q}" + TO_LOG


rule index_shard:
    input:
        robot=DOE_ROBOT,
        box=rules.regular_workspace.output.json,
    output:
        **outputs("index_shard"),
    params:
        **COMMON,
        study=uses("doe", "dead_length_m", "solver", "redundancy", "rotvec_rad", "wrench"),
    log:
        LAYOUT.log("index_shard"),
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job index-shard --threads {threads} --study {params.study_file:q} --shard {wildcards.shard}"
        " --box-file {input.box:q} --table {output.table:q}" + TO_LOG


rule doe:
    input:
        tables=LAYOUT.paths("index_shard", "table"),
    output:
        **outputs(
            "doe",
            figure=("../report/doe.rst", "DOE"),
            effects_figure=("../report/effects.rst", "DOE"),
        ),
    params:
        **COMMON,
        study=uses("doe"),
    log:
        LAYOUT.log("doe"),
    shell:
        "{params.cdpr} job doe --study {params.study_file:q} --tables {input.tables:q} --table {output.table:q}"
        " --effects {output.effects:q} --figure {output.figure:q} --effects-figure {output.effects_figure:q}" + TO_LOG
