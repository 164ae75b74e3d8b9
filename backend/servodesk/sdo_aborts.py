"""SDO abort codes and their meanings for messages a user understands.

The codes and texts live in the protocol core (servodesk_protocol.sdo_abort), shared with the
simulated drives; this module keeps the app's historical names.
"""

from __future__ import annotations

from collections.abc import Mapping

from servodesk_protocol import sdo_abort

ABORT_MEANINGS: Mapping[int, str] = sdo_abort.MEANINGS


def abort_meaning(code: int) -> str:
    """The CiA 301 meaning of an abort code; unknown codes say so (the raw hex is kept apart)."""
    return sdo_abort.describe(code)
