"""Pictures and logs that show how a segmentation was reached (``--debug``)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from rest2art.parts.segment import Segmentation, SegmentedPart
from rest2art.parts.segment.roles import InstanceMask
from rest2art.render.pictures import label
from rest2art.render.raster import PALETTE, blend_masks


def _label_colours(n_labels: int) -> np.ndarray:
    """(n_labels, 3) colours: base grey, then the palette in turn."""
    return PALETTE[np.r_[0, 1 + np.arange(n_labels - 1) % (len(PALETTE) - 1)]]


def _shrink(image: np.ndarray, size: int) -> np.ndarray:
    import cv2

    return cv2.resize(image, (size, size), interpolation=cv2.INTER_AREA)


def view_with_masks(seg: Segmentation, v: int) -> np.ndarray:
    """(H, W, 3) uint8: view ``v`` shaded, each part's lifted mask in that part's colour."""
    colours = _label_colours(len(seg.parts) + 1)
    shown = [(masks[v], colours[k]) for k, masks in enumerate(seg.part_masks, start=1) if v in masks]
    return blend_masks(seg.views[v].shaded(), [m for m, _ in shown], 0.55, np.array([c for _, c in shown]))


def view_with_labels(seg: Segmentation, v: int) -> np.ndarray:
    """(H, W, 3) uint8: view ``v`` with every face coloured by its final label, shaded."""
    view = seg.views[v]
    colours = _label_colours(len(seg.parts) + 1)
    shade = view.shaded().astype(float) / 205.0
    image = np.full(view.face.shape + (3,), 255.0)
    m = view.mask
    image[m] = colours[seg.face_label[view.face[m]]] * np.clip(shade[m], 0, 1)
    return image.astype(np.uint8)


def segmentation_picture(seg: Segmentation, tile: int = 200) -> np.ndarray:
    """(H, W, 3) uint8 contact sheet: top, every view with the lifted part masks; bottom, every
    view with the final face labels. The legend names each colour."""
    if not seg.views:
        raise ValueError("segmentation has no views to draw")
    seen = np.any([view.mask for view in seg.views], axis=0)
    rows, cols = np.nonzero(seen)
    centre = np.array([rows.min() + rows.max(), cols.min() + cols.max()]) // 2
    half = int(0.55 * max(np.ptp(rows), np.ptp(cols))) + 4
    r0, c0 = np.clip(centre - half, 0, None)
    box = (slice(r0, centre[0] + half), slice(c0, centre[1] + half))  # the object, not the empty frame
    masks = np.concatenate([_shrink(view_with_masks(seg, v)[box], tile) for v in range(len(seg.views))], axis=1)
    labels = np.concatenate([_shrink(view_with_labels(seg, v)[box], tile) for v in range(len(seg.views))], axis=1)
    legend = ", ".join(f"{k}:{p.name}" for k, p in enumerate(seg.parts, start=1)) or "no parts found"
    return np.concatenate([label(masks, "masks lifted per view"),
                           label(labels, f"final face labels (0:base, {legend})")], axis=0)


def segmentation_log(seg: Segmentation) -> dict:
    """JSON-ready log: the co-refinement rounds (counts per category per view), pruning, graph
    refinement, and the parts found."""
    def plain(x):
        if isinstance(x, dict):
            return {str(k): plain(v) for k, v in x.items()}
        if isinstance(x, (list, tuple)):
            return [plain(v) for v in x]
        if isinstance(x, np.generic):
            return x.item()
        if isinstance(x, (np.ndarray, InstanceMask, SegmentedPart)):
            return repr(type(x).__name__)
        return x

    return plain({**seg.log, "tree": seg.tree.counts(),
                  "parts": [{"name": p.name, "category": p.category, "parent": p.parent,
                             "normal": np.round(p.normal, 3).tolist(), "views": p.views, "seen": p.seen}
                            for p in seg.parts]})


def write_segmentation_debug(seg: Segmentation, folder: str | Path) -> list[Path]:
    """Write ``segmentation.png`` and ``segmentation_log.json`` into ``folder``."""
    from rest2art.render.pictures import save_png

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    picture, log = folder / "segmentation.png", folder / "segmentation_log.json"
    save_png(segmentation_picture(seg), picture)
    log.write_text(json.dumps(segmentation_log(seg), indent=1))
    return [picture, log]
