"""Stage 1, frame: the canonical up and front of a closed-state mesh (``canonical``)."""
