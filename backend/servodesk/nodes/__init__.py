"""Per-node access: one worker thread per node serializes every blocking canopen call."""
