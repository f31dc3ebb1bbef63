# Cluster execution (workflow/profiles/slurm). Has no effect on a local run.
#
# Rules that do not solve points -- figures, tables aggregated from shards, the summary -- take
# under 2.5 s and 400 MiB each (benchmarks/rule_rss.py, paper study): they run on the host that runs
# Snakemake instead of as SLURM jobs of 10-15 s overhead each. The solver rules are not listed
# here: the profile packs them into group jobs (`groups`, `group-components`), and
# tests/test_cluster_profile.py checks that every rule with a command is in exactly one of the two.
localrules:
    winch_table,
    winch_figure,
    plane_figure,
    subset_figure,
    trajectory_figure,
    volumes,
    volumes_dphi,
    volume_view,
    robot_view,
    regular_workspace,
    doe,
    maps,
    elasticity,
    dead_length,
    summary,
    parity,
    conclusions,
    uncertainty,
    study_budget,
    sag_path,
    sag_corner,

