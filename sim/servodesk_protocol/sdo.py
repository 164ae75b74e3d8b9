"""SDO frames (CiA 301 §7.2.4.3): what the app's bus listeners and the simulated drives' SDO
server both need to recognise. The abort codes themselves are in sdo_abort.py."""

from __future__ import annotations

# byte 0 of an abort frame, client or server (command specifier 4 in bits 5–7); bytes 1–2 are
# the index (little-endian), byte 3 the sub-index, bytes 4–7 the abort code (little-endian)
ABORT_COMMAND = 0x80
