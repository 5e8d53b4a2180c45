"""Reconstruction stages: pure functions on arrays, in the order the data flows."""
