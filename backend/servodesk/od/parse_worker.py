"""Imported first in the forkserver that the dictionary parse workers fork from.

python-can imports asammdf (and with it numpy and pandas) when it is installed, for its MF4
log reader. A parse worker never reads MF4, and the parse runs under an address-space limit
that those libraries' reservations alone would use up, so they are kept out of the workers:
`import asammdf` fails there and python-can simply offers no MF4 support in that process.
"""

from __future__ import annotations

import sys

sys.modules.setdefault("asammdf", None)  # type: ignore[arg-type]  # None: "not importable"
