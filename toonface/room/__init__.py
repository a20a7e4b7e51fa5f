"""The room server: performers and viewers meet in a named room over WebSocket (issue 45's first step)."""
