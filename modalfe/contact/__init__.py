"""Contact and friction simulators (placeholder while developing)."""
