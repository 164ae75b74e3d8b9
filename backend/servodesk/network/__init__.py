"""Network services: NMT, node scan, heartbeat monitor, the tool's SYNC producer."""
