"""Drive parameters by name (service), guided node-id and bitrate changes (node_id), and
parameter sets as DCF files (paramsets) written in a safe order (dcf_order)."""
