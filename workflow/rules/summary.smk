# results/<study>/summary.md: every number of cdpr/data/paper_values.yaml beside ours.


rule summary:
    input:
        **LAYOUT.summary_inputs(),
        paper_values=PAPER_VALUES,
    output:
        **outputs("summary"),
    params:
        **COMMON,
        study=uses(
            "name", "paper_comparison", "dead_length_m", "solver", "doe", "maps", "trajectories", "uncertainty", "redundancy",
            *(["budget"] if STUDY.get("budget") else []),  # the study's error budget (spatial studies only)
        ),
        results=RES,
    log:
        LAYOUT.log("summary"),
    shell:
        "{params.cdpr} job summary --study {params.study_file:q} --results {params.results:q} --markdown {output.markdown:q}"
        " --table {output.table:q}" + TO_LOG
