# h-r_p maps of the global index (Paty 2021 section 4.3, Fig. 17, Table 3): one job per pulley kind.


rule map_kind:
    input:
        box=rules.regular_workspace.output.json,
        robot=DOE_ROBOT,
    output:
        **outputs("map_kind"),
    params:
        **COMMON,
        study=uses("maps", "doe", "dead_length_m", "solver", "redundancy", "wrench"),
    log:
        LAYOUT.log("map_kind"),
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job map --threads {threads} --study {params.study_file:q} --kind {wildcards.kind} --box-file {input.box:q}"
        " --table {output.table:q}" + TO_LOG


rule maps:
    input:
        tables=LAYOUT.paths("map_kind", "table"),
        box=rules.regular_workspace.output.json,
        robot=DOE_ROBOT,
    output:
        **outputs("maps", figure=("../report/maps.rst", "Maps")),
    params:
        **COMMON,
        study=uses("maps", "doe", "dead_length_m", "solver", "redundancy", "wrench"),
    log:
        LAYOUT.log("maps"),
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job maps --threads {threads} --study {params.study_file:q} --box-file {input.box:q} --tables {input.tables:q}"
        " --map {output.map:q} --lines {output.lines:q} --figure {output.figure:q}" + TO_LOG
