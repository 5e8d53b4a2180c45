"""Stage 3, joints: a joint per movable part from geometric rules (``rules``) or from the motion
in videos of the object opening (``video``)."""
