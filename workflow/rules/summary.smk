rule summary:
    input:
        f"{RES}/winch/winch.csv",
        expand(f"{RES}/plane/{{robot}}_{{pulley}}.csv", robot=ROBOTS, pulley=PULLEYS),
        expand(f"{RES}/trajectories/{{robot}}_{{pulley}}.csv", robot=STUDY["trajectories"]["paths"], pulley=PULLEYS),
        f"{RES}/volumes/volumes.csv",
        f"{RES}/doe/rw_c.json",
        f"{RES}/doe/doe.csv",
        f"{RES}/doe/effects.csv",
        f"{RES}/maps/lines.csv",
        f"{RES}/elasticity/bands.csv",
        f"{RES}/elasticity/crossings.csv",
        f"{RES}/dead_length/dead_length.csv",
    output:
        f"{RES}/summary.md",
        f"{RES}/summary.csv",
    shell:
        "{CDPR} job summary --study {STUDY_FILE} --results {RES} --outputs {output}"
