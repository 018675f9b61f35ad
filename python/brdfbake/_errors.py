"""The exceptions of brdfbake.

Every error the package raises is a :class:`brdfbake.Error`. The message is the one line the command-line
tool prints after ``brdfbake <command>:``; ``exit_code`` is the exit code the tool would have returned.
"""


class Error(Exception):
    """A brdfbake error: the message is one complete line."""

    #: The exit code of the command-line tool for the same failure.
    exit_code = 1


class InputError(Error, ValueError):
    """Bad input: a parameter out of range, an unknown kind or name, a file that cannot be read, an
    array of the wrong dtype or shape. The command-line tool exits with 2 for these."""

    exit_code = 2


class ArgumentError(InputError, TypeError):
    """A call with arguments the function does not take (an unknown keyword, a missing argument)."""


class DeviceError(Error, RuntimeError):
    """An OpenCL call failed; the message names the call, the kernel and the OpenCL error."""


class NotAvailableError(Error, RuntimeError):
    """A table kind this build cannot bake."""


class BakeWarning(UserWarning):
    """Something was changed on the way to a file, on request: values beyond binary16's 65504
    clamped (``clamp_f16=True``), an environment's NaN, infinite or negative pixels replaced. The
    command-line tool prints the same line after ``warning:``; the result lists them too
    (``Result.warnings``)."""


for _cls in (Error, InputError, ArgumentError, DeviceError, NotAvailableError, BakeWarning):
    _cls.__module__ = "brdfbake"  # shown as brdfbake.InputError in tracebacks; pickled by that name
del _cls
