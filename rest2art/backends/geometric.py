"""The offline defaults: geometric hierarchy and masks, Lucas-Kanade tracks, no video model,
the template video prompt. Nothing to download, nothing beyond the core install."""

from __future__ import annotations

from rest2art.backends.registry import register


@register("masks", "geometric", "panels, handles and knobs found in the rendered depth, normal and face maps")
def make_geometric_masks(views, face_piece, segment, models):
    from rest2art.parts.segment.roles import GeometricBackend

    return GeometricBackend(views, face_piece, segment)


@register("hierarchy", "geometric", "part tree of the view with most parts, from the geometric masks")
def make_geometric_hierarchy(views, face_piece, masks, segment, models):
    from rest2art.parts.segment.roles import GeometricBackend, GeometricHierarchy

    if not isinstance(masks, GeometricBackend):
        masks = GeometricBackend(views, face_piece, segment)
    return GeometricHierarchy(masks)


@register("tracks", "lucas_kanade", "OpenCV pyramidal Lucas-Kanade with a forward-backward check")
def make_lucas_kanade(models):
    from rest2art.joints.video.tracks import LucasKanadeTracker

    return LucasKanadeTracker()


@register("video", "none", "no video model: motion videos come from --motion-video folders")
def make_no_video(models):
    return None


@register("prompt", "template", "a sentence per movable part from its semantic, and the camera-lock suffix")
def make_template_prompt(models):
    from rest2art.joints.video.source import motion_prompt

    return lambda image, semantics: motion_prompt(semantics)
