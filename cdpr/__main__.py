"""Entry point of ``python -m cdpr`` and of the ``cdpr`` console script."""

import gc
import sys


def run():
    """``cdpr.cli.main.main`` with Python's cyclic garbage collector off.

    A command is a short-lived process whose objects are mostly the ~10^6 long-lived ones of the
    modules it loads (numpy, pandas, numba's compiler). Collecting them while they load and again at
    interpreter exit frees nothing and costs 0.3-0.4 s per command (benchmarks/README.md), about
    a third of a 250,000-point ``cdpr grid``. Reference counting still frees everything else; the
    library itself never touches the collector."""
    gc.disable()
    try:
        from cdpr.cli.main import main  # lazy: after the collector is off
    except KeyboardInterrupt:  # Ctrl-C while loading: main() says the same for a running command
        print("cdpr: interrupted (Ctrl-C)", file=sys.stderr)
        sys.exit(130)
    code = main()
    gc.freeze()  # interpreter exit: do not collect what was loaded
    sys.exit(code)


if __name__ == "__main__":
    run()
