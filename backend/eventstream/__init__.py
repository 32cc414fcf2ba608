"""Server-sent events: "this changed", written with each change, streamed to the phones."""
