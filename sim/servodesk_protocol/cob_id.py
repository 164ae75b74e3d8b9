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

MAX_NODE_ID = 127


def for_node(base: int, node_id: int) -> int:
    """`base + node_id` for a node id 1..127."""
    if not 1 <= node_id <= MAX_NODE_ID:
        raise ValueError(f"node id {node_id} is outside 1..127")
    return base + node_id


def node_services(node_id: int) -> dict[int, str]:
    """The CAN ids one node uses outside its PDOs, each with the service's name."""
    return {
        EMCY + node_id: "EMCY",
        SDO_TX + node_id: "SDO response",
        SDO_RX + node_id: "SDO request",
        HEARTBEAT + node_id: "heartbeat",
    }
