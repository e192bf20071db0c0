# SPDX-License-Identifier: GPL-3.0-or-later
"""sdvi: images as curvilinear-feature-driven subdivision surfaces.

The functions are those of the ``sdvi`` command, on files and numpy arrays; each releases
the GIL while it works, so threads run them in parallel. A file written here is
byte-identical to the one the command writes with the same options.

    import sdvi
    image, report = sdvi.vectorize("photo.png", "photo.sdvi")
    pixels = sdvi.render(image, scale=4)          # float32 (H, W, 4), colours 0..255
    sdvi.compare("photo.sdvi", "photo.png")       # {'psnr_db': ..., 'mssim': ..., ...}

``sdvi.distributed.map_files`` runs one of them over many files on a Dask cluster.
"""

from ._sdvi import Image, compare, compress, load, read_raster, render, vectorize

__all__ = ["Image", "compare", "compress", "load", "read_raster", "render", "vectorize"]
