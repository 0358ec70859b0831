"""The ``designer`` command's entry point: the console script, ``python -m designer`` and ``python -m designer.cli``.

Its first instruction makes Ctrl-C (SIGINT) and SIGTERM print one line and exit 130 and 143 while the
command's modules are still being imported (NumPy, CasADi, matplotlib take a moment); the default handler
would print a Python traceback.  Nothing is written during the imports, so there is nothing to clean up.
:func:`designer.cli.main` then installs the handlers that clean up after a command.  (``import designer``
itself loads nothing heavy, so only the interpreter's own start-up comes before this.)
"""

import contextlib
import os
import signal
import sys

from designer.errors import quiet_after_signal  # light: the handlers below come before every heavy import


def _startup_signal(signum, frame):  # pragma: no cover - ends the process
    os.write(2, b"designer: interrupted\n" if signum == signal.SIGINT else b"designer: terminated (SIGTERM)\n")
    os._exit(128 + signum)


BLAS_THREADS = {"OPENBLAS_NUM_THREADS": "1"}
"""The BLAS thread pool of the command's process (and of the children it starts): one thread.  Its matrices are
small (a few hundred casters at the most), so more threads only spin: on the main job 0.2 s of CPU for no change
in wall time or in any number.  A value the user set stands (e.g. ``OPENBLAS_NUM_THREADS=2 designer ...``)."""


def single_thread_blas() -> None:
    """Set :data:`BLAS_THREADS` in the environment where the user has not, before NumPy is imported."""
    for name, value in BLAS_THREADS.items():
        os.environ.setdefault(name, value)


def main() -> int:
    """Install the start-up handlers, import the command line and run it; returns the exit code."""
    signal.signal(signal.SIGINT, _startup_signal)
    signal.signal(signal.SIGTERM, _startup_signal)
    single_thread_blas()
    from designer.cli import main as cli_main  # the heavy imports, under the handlers above

    code = cli_main()
    if code in (128 + signal.SIGINT, 128 + signal.SIGTERM):
        _end_quietly(code)
    return code


def _end_quietly(code: int) -> None:  # pragma: no cover - ends the process
    """After an interruption, its one line printed and every clean-up of the command done: end the process now.
    Child processes (explore's workers, Dask's) are killed rather than shut down (a shutdown logs about the
    scheduler going away), and the interpreter's exit handlers are skipped (Dask's ``close_clusters`` would
    print tracebacks about the closed loop): nothing but the one line reaches stderr."""
    quiet_after_signal()
    multiprocessing = sys.modules.get("multiprocessing")
    if multiprocessing is not None:
        for child in multiprocessing.active_children():
            with contextlib.suppress(OSError, ValueError, AttributeError):  # gone already
                child.kill()
        # multiprocessing's own exit: children joined, its semaphores unlinked (no "leaked semaphore" warning)
        with contextlib.suppress(Exception):  # the process ends in any case
            multiprocessing.util._exit_function()
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(OSError, ValueError, AttributeError):
            stream.flush()
    os._exit(code)


__all__ = ["main"]
