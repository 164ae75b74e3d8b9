"""COB-ID bases of the pre-defined connection set (CiA 301 §7.3.3): function code + node id."""

from __future__ import annotations

NMT = 0x000  # NMT node control (master -> all)
SYNC = 0x080  # SYNC (default COB-ID of 1005h)
EMCY = 0x080  # EMCY: 80h + node id
TIME = 0x100  # TIME stamp
TPDO1 = 0x180  # TPDO1..4: 180h, 280h, 380h, 480h + node id
RPDO1 = 0x200  # RPDO1..4: 200h, 300h, 400h, 500h + node id
SDO_TX = 0x580  # SDO server -> client (response)
SDO_RX = 0x600  # SDO client -> server (request)
HEARTBEAT = 0x700  # NMT error control: boot-up, heartbeat, node-guarding answer: 700h + node id
LSS_MASTER = 0x7E5
LSS_SLAVE = 0x7E4

PDO_STEP = 0x100  # TPDO2 = TPDO1 + 100h, ...
TPDOS = tuple(TPDO1 + PDO_STEP * n for n in range(4))  # default TPDO1..4 bases
RPDOS = tuple(RPDO1 + PDO_STEP * n for n in range(4))  # default RPDO1..4 bases

CAN_ID_MASK = 0x7FF  # 11-bit identifier (bits 0–10 of a COB-ID object)
# Bits above the identifier in COB-ID objects (1005h, 1014h, 1400h+n, 1800h+n sub 1)
INVALID_BIT = 1 << 31  # service / PDO switched off
EXTENDED_BIT = 1 << 29  # 29-bit identifier
FUNCTION_MASK = 0x780  # 11-bit COB-ID = function code (bits 7–10) + node id (bits 0–6)
NODE_ID_MASK = 0x07F
MAX_NODE_ID = 127


def for_node(base: int, node_id: int) -> int:
    """`base + node_id` for a node id 1..127."""
    if not 1 <= node_id <= MAX_NODE_ID:
        raise ValueError(f"node id {node_id} is outside 1..127")
    return base + node_id


def split(can_id: int) -> tuple[int, int]:
    """(function code base, node id) of an 11-bit CAN id: 0x1A5 -> (0x180, 0x25)."""
    return can_id & FUNCTION_MASK, can_id & NODE_ID_MASK


def node_services(node_id: int) -> dict[int, str]:
    """The CAN ids one node uses outside its PDOs, each with the service's name."""
    return {
        EMCY + node_id: "EMCY",
        SDO_TX + node_id: "SDO response",
        SDO_RX + node_id: "SDO request",
        HEARTBEAT + node_id: "heartbeat",
    }
