# Young's modulus uncertainty (section 5, Fig. 18-19) and the dead-length calibration.
import numpy as np

EL = STUDY["elasticity"]
OPT = STUDY["optimal"]
E_VALUES = [f"{e:.6g}" for e in np.linspace(EL["E_Pa"]["from"], EL["E_Pa"]["to"], EL["E_Pa"]["steps"])]
E_PATH = [f"{float(e):.6g}" for e in EL["E_path_Pa"]]


def opt_args(design, E):
    return pulley_args(OPT[design], E=E)


rule elasticity_shard:
    input:
        robot=ROBOTS[DOE["robot"]],
        box=f"{RES}/doe/rw_c.json",
    output:
        f"{RES}/shards/elasticity/{{design}}_E{{E}}_{{shard}}.parquet",
    params:
        design=lambda w: opt_args(w.design, w.E),
    log:
        f"{RES}/logs/elasticity_{{design}}_E{{E}}_{{shard}}.log",
    threads: SOLVER_THREADS
    shell:
        "{CDPR} grid --threads {threads} --robot {input.robot} {params.design} --box-file {input.box} --n {EL[index_n]}"
        " --shard {wildcards.shard} --shards {EL[shards]} --out {output} > {log} 2>&1"


rule elasticity_path:
    input:
        robot=ROBOTS[DOE["robot"]],
    output:
        f"{RES}/elasticity/path_{{design}}_E{{E}}.csv",
    params:
        design=lambda w: opt_args(w.design, w.E),
    log:
        f"{RES}/logs/elasticity_path_{{design}}_E{{E}}.log",
    threads: SOLVER_THREADS
    shell:
        "{CDPR} trajectory --threads {threads} --robot {input.robot} {params.design} --start {EL[path][start_m]} --end {EL[path][end_m]}"
        " --n {EL[path][points]} --out {output} > {log} 2>&1"


rule elasticity:
    input:
        shards=[f"{RES}/shards/elasticity/{d}_E{e}_{s}.parquet" for d in OPT for e in E_VALUES for s in range(EL["shards"])],
        paths=[f"{RES}/elasticity/path_{d}_E{e}.csv" for d in OPT for e in E_PATH],
    output:
        f"{RES}/elasticity/index_vs_E.csv",
        f"{RES}/elasticity/bands.csv",
        report(f"{RES}/elasticity/index_vs_E.png", caption="../report/elasticity.rst", category="Elasticity"),
        report(f"{RES}/elasticity/paths.png", caption="../report/elasticity_path.rst", category="Elasticity"),
        f"{RES}/elasticity/crossings.csv",
    params:
        E=E_VALUES,
    shell:
        "{CDPR} job elasticity --study {STUDY_FILE} --E-values {params.E} --shards {EL[shards]} --inputs {input.shards} {input.paths} --outputs {output}"


rule dead_length_point:
    input:
        box=f"{RES}/doe/rw_c.json",
    output:
        f"{RES}/shards/dead_length/d{{d}}.csv",
    log:
        f"{RES}/logs/dead_length_{{d}}.log",
    threads: SOLVER_THREADS
    shell:
        "{CDPR} job dead-length-point --threads {threads} --study {STUDY_FILE} --d {wildcards.d} --box-file {input.box} --outputs {output} > {log} 2>&1"


rule dead_length:
    input:
        [f"{RES}/shards/dead_length/d{d:g}.csv" for d in STUDY["dead_length"]["values_m"]],
    output:
        f"{RES}/dead_length/dead_length.csv",
        report(f"{RES}/dead_length/dead_length.png", caption="../report/dead_length.rst", category="Dead length"),
    shell:
        "{CDPR} job dead-length --study {STUDY_FILE} --inputs {input} --outputs {output}"
