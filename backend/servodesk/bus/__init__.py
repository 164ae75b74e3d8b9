"""The CAN bus connection: python-can bus + canopen.Network lifecycle, reconnect, statistics
(`servodesk.bus.connection`). Nothing is imported here: python-can brings asammdf and pandas (a
second of start-up), which the command line's checks and help never need."""
