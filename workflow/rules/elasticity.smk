# Young's modulus uncertainty (Paty 2021 section 5, Fig. 18-19) and the dead-length calibration.


rule elasticity_shard:
    input:
        robot=DOE_ROBOT,
        box=rules.regular_workspace.output.json,
    output:
        **outputs("elasticity_shard"),
    params:
        **COMMON,
        study=uses("elasticity.path", "elasticity.E_path_Pa", "optimal", "doe.robot", "dead_length_m", "solver", "redundancy", "rotvec_rad", "wrench"),
    log:
        LAYOUT.log("elasticity_shard"),
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job elasticity-shard --threads {threads} --study {params.study_file:q} --design {wildcards.design}"
        " --shard {wildcards.shard} --box-file {input.box:q} --table {output.table:q}" + TO_LOG


rule elasticity_path:
    input:
        robot=DOE_ROBOT,
    output:
        **outputs("elasticity_path"),
    params:
        **COMMON,
        study=uses("elasticity", "optimal", "doe", "dead_length_m", "solver", "redundancy", "rotvec_rad", "wrench"),
    log:
        LAYOUT.log("elasticity_path"),
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job elasticity-path --threads {threads} --study {params.study_file:q} --design {wildcards.design}"
        " --modulus {wildcards.E} --table {output.table:q}" + TO_LOG


rule elasticity:
    input:
        tables=LAYOUT.paths("elasticity_shard", "table"),
        paths=LAYOUT.paths("elasticity_path", "table"),
    output:
        **outputs(
            "elasticity",
            figure=("../report/elasticity.rst", "Elasticity"),
            paths_figure=("../report/elasticity_path.rst", "Elasticity"),
        ),
    params:
        **COMMON,
        study=uses("elasticity", "optimal"),
    log:
        LAYOUT.log("elasticity"),
    shell:
        "{params.cdpr} job elasticity --study {params.study_file:q} --tables {input.tables:q} --paths {input.paths:q}"
        " --table {output.table:q} --bands {output.bands:q} --crossings {output.crossings:q} --figure {output.figure:q}"
        " --paths-figure {output.paths_figure:q}" + TO_LOG


rule dead_length_point:
    input:
        box=rules.regular_workspace.output.json,
        robot=DOE_ROBOT,
    output:
        **outputs("dead_length_point"),
    params:
        **COMMON,
        study=uses("dead_length", "pulleys", "plane", "optimal", "elasticity", "doe", "solver", "redundancy", "rotvec_rad", "wrench"),
    log:
        LAYOUT.log("dead_length_point"),
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job dead-length-point --threads {threads} --study {params.study_file:q}"
        " --box-file {input.box:q} --table {output.table:q}" + TO_LOG


rule dead_length:
    input:
        tables=LAYOUT.paths("dead_length_point", "table"),
    output:
        **outputs("dead_length", figure=("../report/dead_length.rst", "Dead length")),
    params:
        **COMMON,
        study=uses("dead_length_m"),
    log:
        LAYOUT.log("dead_length"),
    shell:
        "{params.cdpr} job dead-length --study {params.study_file:q} --tables {input.tables:q} --table {output.table:q}"
        " --figure {output.figure:q}" + TO_LOG
