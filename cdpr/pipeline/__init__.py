"""Study in, files out: the study file, the results-folder layout, the jobs Snakemake runs (tasks),
the uncertainty experiments (uq), the summary, the comparison, the calibration study and the figures."""
