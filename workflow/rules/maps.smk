# h-r_p maps of the global index (section 4.3, Fig. 17): one job per pulley kind over all map cells.


rule map_kind:
    input:
        box=f"{RES}/doe/rw_c.json",
    output:
        f"{RES}/shards/maps/{{kind}}.csv",
    log:
        f"{RES}/logs/map_{{kind}}.log",
    threads: SOLVER_THREADS
    shell:
        "{CDPR} job map --threads {threads} --study {STUDY_FILE} --kind {wildcards.kind} --box-file {input.box} --outputs {output} > {log} 2>&1"


rule maps:
    input:
        rows=expand(f"{RES}/shards/maps/{{kind}}.csv", kind=["SR", "DR"]),
        box=f"{RES}/doe/rw_c.json",
    output:
        f"{RES}/maps/map.csv",
        f"{RES}/maps/lines.csv",
        report(f"{RES}/maps/maps.png", caption="../report/maps.rst", category="Maps"),
    shell:
        "{CDPR} job maps --study {STUDY_FILE} --box-file {input.box} --inputs {input.rows} --outputs {output}"
