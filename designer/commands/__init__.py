"""Sub-commands of the ``designer`` command line; each module defines ``register(subparsers)``."""
