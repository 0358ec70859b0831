"""``python -m designer``: the ``designer`` command (:func:`designer.entry.main`)."""

import sys

from designer.entry import main

sys.exit(main())
