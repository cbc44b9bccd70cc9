"""The one error type users see: a single line naming the file (or thing) and the fix."""


class InputError(Exception):
    """Bad user input: missing or broken files, unknown ids, missing weights.

    The message is one line, names the offending path or value, and says how to fix it.
    The CLI prints it without a traceback.
    """


class Cancelled(Exception):
    """Long work stopped on SIGINT/SIGTERM after saving what it needs to continue; the CLI exits with 130."""
