"""``main(argv)``: parse the command line, run the command, turn a ``CdprError`` into one line and exit code 2,
and Ctrl-C into one line and exit code 130 (the shell's 128 + SIGINT)."""

from __future__ import annotations

import importlib
import os
import sys

from cdpr.cli.parser import build_parser
from cdpr.errors import CdprError


def _command(argv):
    """The subcommand of ``argv`` (its first word that is not an option), or None."""
    return next((a for a in argv if not a.startswith("-")), None)


#: The line and the exit code of a command stopped by Ctrl-C (128 + SIGINT, as a shell reports it).
INTERRUPTED = "cdpr: interrupted (Ctrl-C); no partial output was left"
EXIT_INTERRUPTED = 130


def _euler_to_rotvec(args):
    """``--euler-xyz-deg A B C`` (CASPR's Euler XYZ angles [deg], intrinsic: R = Rx(A) Ry(B) Rz(C),
    CASPR's ``SphericalEulerXYZ.RelRotationMatrix``) becomes ``args.rotvec`` [rad], the one
    orientation the commands read (scipy's ``from_euler('XYZ')``: upper case is intrinsic)."""
    deg = getattr(args, "euler_xyz_deg", None)
    if deg is None:
        return
    from scipy.spatial.transform import Rotation  # lazy: --euler-xyz-deg only (not for --help)

    args.rotvec = [float(x) for x in Rotation.from_euler("XYZ", deg, degrees=True).as_rotvec()]


def main(argv=None):
    """Run ``cdpr`` with ``argv`` (default ``sys.argv[1:]``); returns the exit code (0, 2 for a refused
    input, 130 after Ctrl-C: one line, no traceback; every output is written atomically, so none is
    left half-written)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        args = build_parser(jobs=_command(argv) == "job").parse_args(argv)
        _euler_to_rotvec(args)
        module, func = args.run
        # lazy: the command's module (numpy, the models) is loaded only once the arguments are read
        command = getattr(importlib.import_module(module), func)
        import numpy as np  # lazy: loaded by every command's module already; not for --help

        with np.errstate(all="ignore"):  # no numpy floating-point warning reaches a user: statuses say it
            code = command(args)  # None (0), or the exit code of a command that reports its own errors
        sys.stdout.flush()  # a full disk or a closed pipe shows here, not at interpreter exit
    except CdprError as exc:
        print(f"cdpr: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(INTERRUPTED, file=sys.stderr, flush=True)
        return EXIT_INTERRUPTED
    except BrokenPipeError:  # e.g. `cdpr ... | head`: the reader left; stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    except FileNotFoundError as exc:  # an input that is not there (outputs' folders are created)
        print(f"cdpr: error: {exc.filename or exc}: no such file or folder", file=sys.stderr)
        return 2
    except OSError as exc:  # e.g. a full disk (ENOSPC), for standard output or an output file
        where = f" {exc.filename}" if exc.filename else " the output"
        print(f"cdpr: error: cannot write{where} ({exc.strerror or exc})", file=sys.stderr)
        _quiet_stdout()
        return 1
    return code if isinstance(code, int) else 0


def _quiet_stdout():
    """Point standard output at /dev/null so that the interpreter's final flush of what could not be
    written raises nothing more."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except OSError:
        pass
