"""Input and output at the edges: reading a mesh (``load``), writing a folder atomically (``atomic``)."""
