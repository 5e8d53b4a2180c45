"""Stage 2, parts: separate pieces grouped into a base and movable parts (``pieces``); a fused
surface cut into parts from rendered views (``segment``)."""
