"""Stage 6, collision: boxes for boards (``boxes``), convex hulls and CoACD for the rest
(``hulls``), and clearance between moving parts (``clearance``)."""
