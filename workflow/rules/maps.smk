# h-r_p maps of the global index (section 4.3, Fig. 17), one job per pulley kind x h row.
import numpy as np

MAPS = STUDY["maps"]
H_VALUES = [f"{h:.4f}" for h in np.round(np.arange(MAPS["h_m"]["from"], MAPS["h_m"]["to"] + 1e-9, MAPS["h_m"]["step"]), 10)]
RP_MIN = MAPS["r_p_m"]["from"]
H_ROWS = [h for h in H_VALUES if float(h) > RP_MIN + 1e-12]


rule map_row:
    input:
        box=f"{RES}/doe/rw_c.json",
    output:
        f"{RES}/shards/maps/{{kind}}_h{{h}}.csv",
    log:
        f"{RES}/logs/map_{{kind}}_h{{h}}.log",
    threads: SOLVER_THREADS
    shell:
        "{CDPR} job map-row --threads {threads} --study {STUDY_FILE} --kind {wildcards.kind} --h {wildcards.h} --box-file {input.box} --outputs {output} > {log} 2>&1"


rule maps:
    input:
        rows=expand(f"{RES}/shards/maps/{{kind}}_h{{h}}.csv", kind=["SR", "DR"], h=H_ROWS),
        box=f"{RES}/doe/rw_c.json",
    output:
        f"{RES}/maps/map.csv",
        f"{RES}/maps/lines.csv",
        report(f"{RES}/maps/maps.png", caption="../report/maps.rst", category="Maps"),
    shell:
        "{CDPR} job maps --study {STUDY_FILE} --box-file {input.box} --inputs {input.rows} --outputs {output}"
