# What the cables' weight adds (issue 38; cdpr.pipeline.sag): for a study with a `sag` section (the
# large study, config/studies/large.yaml) the path with and without sag and the cables at a corner
# pose drawn from the catenary. `large_study` is what `make reproduce` asks of that study: the plane
# maps and paths of both robots (with and without sag) and these two (Layout.large_targets).


rule sag_path:
    input:
        tables=LAYOUT.paths("trajectory_table", "table"),
    output:
        **outputs("sag_path", figure=("../report/sag.rst", "Sag")),
    params:
        **COMMON,
        study=uses("sag", "trajectories", "pulleys", "redundancy"),
    log:
        LAYOUT.log("sag_path"),
    shell:
        "{params.cdpr} job sag-path --study {params.study_file:q} --tables {input.tables:q} --table {output.table:q}"
        " --figure {output.figure:q}" + TO_LOG


rule sag_corner:
    input:
        robot=lambda w: ROBOTS[STUDY["sag"]["robot"]],
    output:
        **outputs("sag_corner", figure=("../report/sag.rst", "Sag")),
    params:
        **COMMON,
        study=uses("sag", "robots", "dead_length_m", "rotvec_rad", "redundancy", "wrench"),
    log:
        LAYOUT.log("sag_corner"),
    shell:
        "{params.cdpr} job sag-corner --study {params.study_file:q} --table {output.table:q}"
        " --figure {output.figure:q}" + TO_LOG


rule large_study:
    input:
        LAYOUT.large_targets() if STUDY.get("sag") else [],
