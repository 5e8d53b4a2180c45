"""Numerical tolerances shared by every stage: guards of floating-point arithmetic, not judgements
about objects.

A threshold that decides something about an object (how far a handle stands out, how tall a
fridge is) is a field of the stage's config in ``rest2art.config``; what is here only keeps the
arithmetic sound, and changing it changes no result on sound input.
"""

TINY = 1e-12
"""Floor of a denominator or a vector norm (any unit): keeps a division finite."""

SAME_POINT = 1e-9
"""m: coordinates closer than this are equal (plane tests, barycentric edges, repeated hits)."""

EMPTY_VOLUME = 1e-9
"""m^3: a solid or hull with less volume than this is empty."""

RAY_NUDGE = 1e-5
"""m: a ray cast from a surface starts this far off it, so that it does not hit its own face."""

FACING_COS = 0.95
"""A face faces a direction when the cosine between its normal and that direction exceeds this
(about 18 degrees)."""

PARALLEL_COS = 0.999
"""Two unit axes are parallel when the absolute cosine between them exceeds this."""

PERPENDICULAR_COS = 0.02
"""... and perpendicular when it is below this."""
