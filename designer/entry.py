"""The ``designer`` command's entry point: the console script, ``python -m designer`` and ``python -m designer.cli``.

Its first instruction makes Ctrl-C (SIGINT) and SIGTERM print one line and exit 130 and 143 while the
command's modules are still being imported (NumPy, CasADi, matplotlib take a moment); the default handler
would print a Python traceback.  Nothing is written during the imports, so there is nothing to clean up.
:func:`designer.cli.main` then installs the handlers that clean up after a command.  (``import designer``
itself loads nothing heavy, so only the interpreter's own start-up comes before this.)
"""

import os
import signal


def _startup_signal(signum, frame):  # pragma: no cover - ends the process
    os.write(2, b"designer: interrupted\n" if signum == signal.SIGINT else b"designer: terminated (SIGTERM)\n")
    os._exit(128 + signum)


def main() -> int:
    """Install the start-up handlers, import the command line and run it; returns the exit code."""
    signal.signal(signal.SIGINT, _startup_signal)
    signal.signal(signal.SIGTERM, _startup_signal)
    from designer.cli import main as cli_main  # the heavy imports, under the handlers above

    return cli_main()


__all__ = ["main"]
