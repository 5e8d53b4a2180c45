"""Geometry helpers shared by every stage: vectors and transforms (``basics``), FCL queries
(``fcl``), offsets of a mesh along its normals (``offsets``)."""
