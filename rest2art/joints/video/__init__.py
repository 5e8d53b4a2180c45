"""Joints from motion: tracks in generated or supplied videos (``source``, ``tracks``), lifted to
3D and fitted to revolute or prismatic motion (``motion``, ``fit``, ``classify``, ``estimate``),
then grounded on the part's geometry (``grounding``)."""
