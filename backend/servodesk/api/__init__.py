"""HTTP and WebSocket layer: thin routers over the services, one error mapping."""
