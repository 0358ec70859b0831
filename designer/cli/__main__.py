"""``python -m designer.cli``: the ``designer`` command (:func:`designer.entry.main`)."""

import sys

from designer.entry import main

sys.exit(main())
