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
