# results/<study>/conclusions.md and .csv: do the paper's conclusions hold on this study's robot?
# Only for a study whose `conclusions` key names a reference study (the paper's robot in physical
# mode) and its results folder, which must have been run first (`make reproduce` runs the physical
# study before CoGiRo's). cdpr.pipeline.conclusions; cdpr.pipeline.results lists the rule.
from cdpr.pipeline.conclusions import conclusion_inputs, reference_of

REFERENCE = reference_of(STUDY)


rule conclusions:
    input:
        own=conclusion_inputs(STUDY, RES),
        reference=conclusion_inputs(*REFERENCE) if REFERENCE else [],
        reference_study=STUDY["conclusions"]["study"] if REFERENCE else [],
    output:
        **outputs("conclusions"),
    params:
        **COMMON,
        study=uses("name", "conclusions", "doe", "plane", "volumes", "pulleys", "optimal"),
        results=RES,
    log:
        LAYOUT.log("conclusions"),
    shell:
        "{params.cdpr} job conclusions --study {params.study_file:q} --results {params.results:q}"
        " --table {output.table:q} --markdown {output.markdown:q}" + TO_LOG
