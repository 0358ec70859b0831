"""``designer studio``: the trade-off live in the browser.

A Dash app (:mod:`designer.studio.app`: its callbacks) on top of the same API the command line uses:
:mod:`designer.studio.state` turns controls into problem-file data and back (URL, TOML),
:mod:`designer.studio.view` computes what is shown, :mod:`designer.studio.figures` draws it,
:mod:`designer.studio.layout` is the page and :mod:`designer.studio.panels` the panels the callbacks fill in.
:func:`serve` runs it on 127.0.0.1.  Dash is imported only when the app is built.
"""

from __future__ import annotations

from designer.studio.server import make_server, serve

__all__ = ["make_server", "serve"]
