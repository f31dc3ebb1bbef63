"""The command line ``cdpr <command> ...``: ``main`` (cdpr.cli.main), the parser (parser, options), the
commands (commands) and the pipeline jobs (job)."""
