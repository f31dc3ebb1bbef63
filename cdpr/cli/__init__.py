"""The command line: ``cdpr <command> ...`` (parser and options, commands, pipeline jobs)."""
