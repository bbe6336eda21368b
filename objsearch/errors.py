"""The one error type for bad user input: the CLI prints its message and exits with 2."""


class UserError(Exception):
    """Bad input from the user (an unknown name, a corrupt file, a malformed line).

    The message names the input and says how to fix it; the CLI shows it without a
    traceback and exits with status 2.
    """

    exit_code = 2
