"""Articulation from motion evidence: tracks, motion type, reprojection fitting, consensus, and
the mesh-grounded judgement that every joint hypothesis passes (see each module)."""
