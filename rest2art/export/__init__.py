"""Stage 7, export: the asset folder with articulation.json, URDF, MJCF and meshes (``writers``)."""
