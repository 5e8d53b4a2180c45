"""Pictures and cameras: a pinhole camera (``camera``), a CPU rasteriser (``raster``) and the
pictures of an asset people look at (``pictures``)."""
