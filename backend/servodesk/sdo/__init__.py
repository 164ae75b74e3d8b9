"""SDO access for the API: typed single reads/writes (service), "upload all" jobs (jobs), the
value codec (codec) and chunked bulk reading on a node's worker thread (bulk)."""
