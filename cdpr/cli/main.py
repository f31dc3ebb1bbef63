"""``main(argv)``: parse the command line, run the command, turn a ``CdprError`` into one line and exit code 2."""

from __future__ import annotations

import importlib
import os
import sys

from cdpr.cli.parser import build_parser
from cdpr.errors import CdprError


def _command(argv):
    """The subcommand of ``argv`` (its first word that is not an option), or None."""
    return next((a for a in argv if not a.startswith("-")), None)


def main(argv=None):
    """Run ``cdpr`` with ``argv`` (default ``sys.argv[1:]``); returns the exit code (0, or 2 for a refused input)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        args = build_parser(jobs=_command(argv) == "job").parse_args(argv)
        module, func = args.run
        # lazy: the command's module (numpy, the models) is loaded only once the arguments are read
        getattr(importlib.import_module(module), func)(args)
    except CdprError as exc:
        print(f"cdpr: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # e.g. `cdpr ... | head`: the reader left; stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    return 0
