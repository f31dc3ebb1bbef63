# cdpr study workflow: a study is a YAML file; a point is a row; a figure is an aggregation of rows.
# Layout: workflow/rules/*.smk hold the wiring, the cdpr library holds the physics.
from snakemake.utils import min_version, validate

min_version("9.0")


configfile: "config/config.yaml"


validate(config, "workflow/schemas/config.schema.yaml")


include: "workflow/rules/common.smk"
include: "workflow/rules/winch.smk"
include: "workflow/rules/planes.smk"
include: "workflow/rules/trajectories.smk"
include: "workflow/rules/volumes.smk"
include: "workflow/rules/robot.smk"
include: "workflow/rules/doe.smk"
include: "workflow/rules/maps.smk"
include: "workflow/rules/elasticity.smk"
include: "workflow/rules/uncertainty.smk"
include: "workflow/rules/budget.smk"
include: "workflow/rules/summary.smk"
include: "workflow/rules/comparison.smk"
include: "workflow/rules/calibration.smk"
include: "workflow/rules/hangprinter.smk"
include: "workflow/rules/parity.smk"
include: "workflow/rules/conclusions.smk"
include: "workflow/rules/large.smk"


rule reproduce_paper:
    default_target: True
    input:
        all_targets(),


include: "workflow/rules/cluster.smk"
