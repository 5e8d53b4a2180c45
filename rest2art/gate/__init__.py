"""Stage 4, the plausibility gate: does the articulated reading look like the object
(``plausibility``)?"""
