"""Pictures of a catalog entry: closed, opened, a thumbnail and one animation per joint.

Drawn with the project's renderer (``rest2art.render``); animations are animated WebP written
with Pillow. Every picture is a pure function of the asset; only ``write_pictures`` touches files.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rest2art.asset import ArticulatedAsset
from rest2art.config import CatalogConfig
from rest2art.render.pictures import closed_and_open, render_asset, save_png

OPEN_FRACTION = 0.8
"""Share of each joint's range shown in the opened picture (as ``rest2art.render``)."""


def joint_frames(asset: ArticulatedAsset, joint: str, frames: int, size: int) -> list[np.ndarray]:
    """(size, size, 3) uint8 pictures of ``joint`` moved from 0 to its upper limit in ``frames``
    even steps, the other joints closed."""
    upper = next(j.limit[1] for j in asset.joints if j.name == joint)
    return [render_asset(asset, {joint: float(v)}, size) for v in np.linspace(0.0, upper, frames)]


def save_animation(frames: list[np.ndarray], path: str | Path, frame_ms: int) -> None:
    """Animated WebP (loops) playing ``frames`` forward then back."""
    from PIL import Image

    images = [Image.fromarray(f) for f in frames + frames[-2:0:-1]]
    images[0].save(path, format="WEBP", save_all=True, append_images=images[1:], duration=frame_ms, loop=0,
                   lossless=False, quality=80, method=4)


def animation_name(joint: str) -> str:
    """File name of a joint's animation inside the entry folder."""
    return f"media/{joint}.webp"


def write_pictures(asset: ArticulatedAsset, folder: str | Path, config: CatalogConfig,
                   animations: bool = True) -> dict[str, str]:
    """Write ``thumbnail.png`` (closed | opened, axes drawn) and, with ``animations``,
    ``media/closed.png``, ``media/opened.png`` and ``media/<joint>.webp`` per movable joint into
    ``folder``; returns {picture: relative path}."""
    folder = Path(folder)
    out = {"thumbnail": "thumbnail.png"}
    save_png(closed_and_open(asset, config.thumbnail_size, OPEN_FRACTION, axes=True), folder / out["thumbnail"])
    if not animations:
        return out
    (folder / "media").mkdir(exist_ok=True)
    opened = {j.name: OPEN_FRACTION * j.limit[1] for j in asset.movable_joints}
    out["closed"], out["opened"] = "media/closed.png", "media/opened.png"
    save_png(render_asset(asset, None, config.render_size, axes=True), folder / out["closed"])
    save_png(render_asset(asset, opened, config.render_size), folder / out["opened"])
    for joint in asset.movable_joints:
        out[joint.name] = animation_name(joint.name)
        save_animation(joint_frames(asset, joint.name, config.animation_frames, config.animation_size),
                       folder / out[joint.name], config.animation_frame_ms)
    return out
