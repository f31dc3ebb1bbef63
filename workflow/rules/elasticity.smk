# Young's modulus uncertainty (Paty 2021 section 5, Fig. 18-19) and the dead-length calibration.


rule elasticity_shard:
    input:
        robot=DOE_ROBOT,
        box=rules.regular_workspace.output.json,
    output:
        table=f"{RES}/shards/elasticity/{{design}}_E{{E}}_{{shard}}.parquet",
    params:
        design=lambda w: pulley_args(OPT[w.design], E=w.E),
        n=EL["index_n"],
        shards=EL["shards"],
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/elasticity_{{design}}_E{{E}}_{{shard}}.log",
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} grid --threads {threads} --robot {input.robot} {params.design} --box-file {input.box} --n {params.n}"
        " --shard {wildcards.shard} --shards {params.shards} --out {output.table} > {log} 2>&1"


rule elasticity_path:
    input:
        robot=DOE_ROBOT,
    output:
        table=f"{RES}/elasticity/path_{{design}}_E{{E}}.csv",
    params:
        design=lambda w: pulley_args(OPT[w.design], E=w.E),
        path=EL["path"],
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/elasticity_path_{{design}}_E{{E}}.log",
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} trajectory --threads {threads} --robot {input.robot} {params.design} --start {params.path[start_m]} --end {params.path[end_m]}"
        " --n {params.path[points]} --out {output.table} > {log} 2>&1"


rule elasticity:
    input:
        tables=[f"{RES}/shards/elasticity/{d}_E{e}_{s}.parquet" for d in OPT for e in E_VALUES for s in range(EL["shards"])],
        paths=[f"{RES}/elasticity/path_{d}_E{e}.csv" for d in OPT for e in E_PATH],
    output:
        table=f"{RES}/elasticity/index_vs_E.csv",
        bands=f"{RES}/elasticity/bands.csv",
        crossings=f"{RES}/elasticity/crossings.csv",
        figure=report(f"{RES}/elasticity/index_vs_E.png", caption="../report/elasticity.rst", category="Elasticity"),
        pdf=f"{RES}/elasticity/index_vs_E.pdf",
        paths_figure=report(f"{RES}/elasticity/paths.png", caption="../report/elasticity_path.rst", category="Elasticity"),
        paths_pdf=f"{RES}/elasticity/paths.pdf",
    params:
        study=uses("elasticity", "optimal"),
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/elasticity.log",
    shell:
        "{params.cdpr} job elasticity --study {params.study_file} --tables {input.tables} --paths {input.paths} --table {output.table}"
        " --bands {output.bands} --crossings {output.crossings} --figure {output.figure} --paths-figure {output.paths_figure} > {log} 2>&1"


rule dead_length_point:
    input:
        box=rules.regular_workspace.output.json,
        robot=DOE_ROBOT,
    output:
        table=f"{RES}/shards/dead_length/d{{d}}.csv",
    params:
        study=uses("dead_length", "pulleys", "plane", "optimal", "elasticity", "doe", "solver", "redundancy"),
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/dead_length_{{d}}.log",
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job dead-length-point --threads {threads} --study {params.study_file} --d {wildcards.d} --box-file {input.box} --table {output.table} > {log} 2>&1"


rule dead_length:
    input:
        tables=[f"{RES}/shards/dead_length/d{d:g}.csv" for d in STUDY["dead_length"]["values_m"]],
    output:
        table=f"{RES}/dead_length/dead_length.csv",
        figure=report(f"{RES}/dead_length/dead_length.png", caption="../report/dead_length.rst", category="Dead length"),
        pdf=f"{RES}/dead_length/dead_length.pdf",
    params:
        study=uses("dead_length_m"),
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/dead_length.log",
    shell:
        "{params.cdpr} job dead-length --study {params.study_file} --tables {input.tables} --table {output.table} --figure {output.figure} > {log} 2>&1"
