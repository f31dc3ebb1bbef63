# h-r_p maps of the global index (Paty 2021 section 4.3, Fig. 17, Table 3): one job per pulley kind.


rule map_kind:
    input:
        box=rules.regular_workspace.output.json,
        robot=DOE_ROBOT,
    output:
        table=f"{RES}/shards/maps/{{kind}}.csv",
    params:
        study=uses("maps", "doe", "dead_length_m", "solver", "redundancy"),
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/map_{{kind}}.log",
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job map --threads {threads} --study {params.study_file} --kind {wildcards.kind} --box-file {input.box} --table {output.table} > {log} 2>&1"


rule maps:
    input:
        tables=expand(f"{RES}/shards/maps/{{kind}}.csv", kind=map_kinds(STUDY)),
        box=rules.regular_workspace.output.json,
        robot=DOE_ROBOT,
    output:
        map=f"{RES}/maps/map.csv",
        lines=f"{RES}/maps/lines.csv",
        figure=report(f"{RES}/maps/maps.png", caption="../report/maps.rst", category="Maps"),
        pdf=f"{RES}/maps/maps.pdf",
    params:
        study=uses("maps", "doe", "dead_length_m", "solver", "redundancy"),
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/maps.log",
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job maps --threads {threads} --study {params.study_file} --box-file {input.box} --tables {input.tables} --map {output.map}"
        " --lines {output.lines} --figure {output.figure} > {log} 2>&1"
