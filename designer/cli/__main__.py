"""``python -m designer.cli``: the ``designer`` command.

Python has imported this package (``designer/cli/__init__.py``, the heavy part) before this file runs, so the
start-up signal handlers of :mod:`designer.entry` would come too late here: :func:`designer.cli.main` is called
directly (it installs the command's own handlers).  The console script and ``python -m designer`` go through
:func:`designer.entry.main`.
"""

import sys

from designer.cli import main

sys.exit(main())
