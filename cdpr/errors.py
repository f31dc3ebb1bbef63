"""Project exception types: one sentence for the user, no traceback from deep inside numpy."""


class CdprError(Exception):
    """Base class of every error the library raises on purpose."""


class ConfigError(CdprError, ValueError):
    """A configuration file (or command-line override) holds a value that is not allowed.

    The message names the file, the key and what is allowed.
    """

    def __init__(self, source, key, message):
        self.source = str(source)
        self.key = key
        self.detail = message
        where = f"{self.source}: key '{key}'" if key else self.source
        super().__init__(f"{where}: {message}")


def raise_problems(source, problems):
    """Raise the problems a file's checks collected: none, nothing; one, itself; several, one
    ConfigError naming ``source`` and listing them (``N problems: key 'a': ...; key 'b': ...``), a
    key once (the first problem found for it)."""
    first = {}
    for e in problems:
        first.setdefault(e.key, e)
    problems = list(first.values())
    if len(problems) == 1:
        raise problems[0]
    if problems:
        listed = "; ".join(f"key '{e.key}': {e.detail}" if e.key else e.detail for e in problems)
        exc = ConfigError(source, None, f"{len(problems)} problems: {listed}")
        exc.problems = problems  # each on its own (``cdpr study check`` prints one line per problem)
        raise exc
