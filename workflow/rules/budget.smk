# The error budget of a rigid platform (cdpr.analyses.budget; Paty 2021 pulley geometry and elasticity,
# Métillon 2022's winch exit point): per optimal design on the DOE robot, over the index_n^3 grid of
# RW_C at the study's orientation, each effect alone, all together, the interaction and what
# compensating each leaves, in position and orientation. Only for a spatial study with a `budget:`
# key (a point-mass study has the comparison's budget, workflow/rules/comparison.smk); the rules
# are defined for every study so that the cluster profile can name them (cdpr.pipeline.results gates
# their jobs).
BUDGET = STUDY.get("budget")


rule study_budget_design:
    input:
        box=rules.regular_workspace.output.json,
        robot=DOE_ROBOT,
    output:
        **outputs("study_budget_design"),
    wildcard_constraints:
        design="|".join(OPT),
    params:
        **COMMON,
        study=uses("budget", "optimal", "doe", "dead_length_m", "rotvec_rad", "wrench"),
    log:
        LAYOUT.log("study_budget_design"),
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job study-budget-design --threads {threads} --study {params.study_file:q} --design {wildcards.design}"
        " --box-file {input.box:q} --table {output.table:q}" + TO_LOG


rule study_budget:
    input:
        tables=LAYOUT.paths("study_budget_design", "table"),
    output:
        **outputs("study_budget", figure=("../report/study_budget.rst", "Error budget")),
    params:
        **COMMON,
        study=uses("budget", "optimal", "doe"),
    log:
        LAYOUT.log("study_budget"),
    shell:
        "{params.cdpr} job study-budget --study {params.study_file:q} --tables {input.tables:q} --table {output.table:q}"
        " --figure {output.figure:q}" + TO_LOG
