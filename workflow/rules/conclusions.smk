# results/<study>/conclusions.md and .csv: do the paper's conclusions hold on this study's robot?
# Only for a study whose `conclusions` key names a reference study (the paper's robot in physical
# mode) and its results folder, which must have been run first (`make reproduce` runs the physical
# study before CoGiRo's). cdpr.pipeline.conclusions; cdpr.pipeline.results lists the rule.
from cdpr.pipeline.conclusions import conclusion_inputs, reference_of
from cdpr.pipeline.results import check_complete

REFERENCE = reference_of(STUDY)
if REFERENCE:  # one line before any job when the reference study has not been run
    try:
        check_complete(
            REFERENCE[1],
            conclusion_inputs(*REFERENCE),
            f"the conclusions page of study {STUDY['name']!r} (its `conclusions` key: run the reference study first, as make reproduce does, or remove the key)",
        )
    except CdprError as exc:
        raise WorkflowError(f"invalid study configuration: {STUDY_FILE}: conclusions.results: {exc}")


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
