# results/<study>/summary.md: every number of cdpr/data/paper_values.yaml beside ours.


rule summary:
    input:
        winch=f"{RES}/winch/winch.csv",
        planes=expand(f"{RES}/plane/{{robot}}_{{pulley}}.csv", robot=ROBOTS, pulley=PULLEYS),
        paths=expand(f"{RES}/trajectories/{{robot}}_{{pulley}}.csv", robot=PATHS, pulley=PULLEYS),
        minmax=f"{RES}/trajectories/trajectories_minmax.csv",
        volumes=f"{RES}/volumes/volumes.csv",
        rw_c=f"{RES}/doe/rw_c.json",
        doe=f"{RES}/doe/doe.csv",
        effects=f"{RES}/doe/effects.csv",
        lines=f"{RES}/maps/lines.csv",
        bands=f"{RES}/elasticity/bands.csv",
        crossings=f"{RES}/elasticity/crossings.csv",
        dead_length=f"{RES}/dead_length/dead_length.csv",
        uncertainty=[f"{RES}/uncertainty/bands.csv", f"{RES}/uncertainty/sobol.csv"] if STUDY.get("uncertainty") else [],
        paper_values="cdpr/data/paper_values.yaml",
    output:
        markdown=f"{RES}/summary.md",
        table=f"{RES}/summary.csv",
    params:
        study=uses(
            "name", "paper_comparison", "dead_length_m", "solver", "doe", "maps", "trajectories", "uncertainty", "redundancy"
        ),
        cdpr=CDPR,
        study_file=STUDY_FILE,
        results=lambda w, output: str(Path(output.table).parent),
        code=CODE,
    log:
        f"{RES}/logs/summary.log",
    shell:
        "{params.cdpr} job summary --study {params.study_file} --results {params.results} --markdown {output.markdown} --table {output.table} > {log} 2>&1"
