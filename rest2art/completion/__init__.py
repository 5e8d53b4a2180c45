"""Stage 5, completion: every part as closed solids with mass and inertia, and the solids its
collision is built from (``solids``)."""
