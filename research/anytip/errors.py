"""The one exception family anytip raises for bad input: the CLI prints these without a traceback."""


class AnytipError(Exception):
    """Bad input or state that a user can fix; the message names the file, key or value."""
